/*
 * separable_step: one shading step of a separable renderer (pbrt's SeparableBSSRDF and its
 * kin) with a bssrdf-zoo table, on a flat slab, repeated to estimate the effective albedo.
 *
 * Light enters at the origin of the surface z = 0 at incidence theta. The renderer draws the
 * exit distance r from the table's radial distribution (bssrdf_table_sample_radius) and an
 * azimuth uniformly in its own tangent frame, finds the exit point with a probe ray along the
 * normal, and weights the hit by S over the density of the point. With p_r the density per
 * mm of r (bssrdf_table_pdf_radius) and the azimuth uniform, the point's density per mm^2 is
 *
 *     p_A = p_r(r) / (2 pi r).
 *
 * Write S(r, phi) = S_bar(r) F(r, phi), F = bssrdf_table_angular_factor (its mean over phi
 * is 1). Two weights follow:
 *
 *   separable:   S_bar is the sampler's radial profile rho_eff p_r / (2 pi r), so
 *                w = S_bar F / p_A = rho_eff(theta) F(r, phi): its mean is rho_eff(theta)
 *                exactly;
 *   full value:  S from bssrdf_table_eval, w = S / p_A: its mean is the integral of the
 *                evaluated S over the plane, rho_eff to about 1e-4 (evaluation interpolates
 *                the energy along r in log space, the sampler with the plain spline).
 *
 * Both are per unit power entering the medium: a renderer multiplies by its Fresnel terms.
 * The program prints both means with their standard errors next to rho_eff(theta) from
 * bssrdf_table_effective_albedo, for the green channel's medium of MATERIAL.
 *
 *   cargo build --release -p bssrdf-capi
 *   cc -std=c99 -O2 -I include examples/c/separable_step.c target/release/libbssrdf.a \
 *      -lpthread -ldl -lm -o separable_step        # Linux; macOS needs no extra -l flags
 *   ./separable_step scene.bssrdf MATERIAL THETA_DEGREES [DRAWS]
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "bssrdf_zoo.h"

static const double TWO_PI = 6.283185307179586;

/* Stops the program with the failure of a call that returned `status`, unless it succeeded
 * (the operating system closes the library). */
static void require(int status, const char *call) {
    if (status != BSSRDF_OK) {
        fprintf(stderr, "%s: %s: %s\n", call, bssrdf_status_name(status),
                bssrdf_last_error_message());
        exit(1);
    }
}

/* SplitMix64: a uniform double in [0, 1) from the top 53 bits. */
static double next_uniform(uint64_t *state) {
    uint64_t z = (*state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

/* The medium of one shading point: a table and (rho', sigma_t') on it. */
typedef struct medium {
    const bssrdf_library *library;
    size_t table;
    double rho_prime, sigma_t_prime;
} medium;

/* The weights of one shading step for light entering at the origin at incidence theta
 * (radians), its plane of incidence the x-z plane, the refracted beam travelling towards +x
 * (the table's phi = 0). `frame` is the azimuth of the renderer's own tangent frame, which
 * need not follow the plane of incidence. A draw with nothing to sample has weight 0. */
static void shading_step(const medium *m, double theta, double rho_eff, double frame,
                         uint64_t *rng, double *out_separable, double *out_full) {
    bssrdf_radial_sample d;
    double u_r = next_uniform(rng), u_phi = next_uniform(rng);
    double azimuth, hit_x, hit_y, r, phi, pdf_r, factor, value, pdf_area, s_bar;
    int status;
    *out_separable = *out_full = 0.0;
    /* Sample the exit distance from the table's radial distribution */
    status = bssrdf_table_sample_radius(m->library, m->table, m->rho_prime, m->sigma_t_prime,
                                        theta, u_r, &d);
    if (status == BSSRDF_ERROR_NO_SAMPLE) {
        return;
    }
    require(status, "bssrdf_table_sample_radius");
    /* Pick the azimuth uniformly in the renderer's frame; the probe ray along the normal
     * through (r cos a, r sin a) hits the flat slab there */
    azimuth = frame + TWO_PI * u_phi;
    hit_x = d.r * cos(azimuth);
    hit_y = d.r * sin(azimuth);
    /* The hit in the table's coordinates: distance and azimuth from the plane of incidence */
    r = hypot(hit_x, hit_y);
    phi = atan2(hit_y, hit_x);
    /* The density of the hit per mm^2, from the radial density at the hit (a renderer with
     * several probe axes sums such densities) */
    require(bssrdf_table_pdf_radius(m->library, m->table, m->rho_prime, m->sigma_t_prime,
                                    theta, r, &pdf_r),
            "bssrdf_table_pdf_radius");
    pdf_area = pdf_r / (TWO_PI * r);
    if (!(pdf_area > 0.0)) {
        return;
    }
    /* Separable weight: the sampler's radial profile times the angular factor */
    require(bssrdf_table_angular_factor(m->library, m->table, m->rho_prime, m->sigma_t_prime,
                                        theta, r, phi, &factor),
            "bssrdf_table_angular_factor");
    s_bar = rho_eff * pdf_r / (TWO_PI * r);
    *out_separable = s_bar * factor / pdf_area;
    /* Full weight: the table's value at the hit */
    require(bssrdf_table_eval(m->library, m->table, m->rho_prime, m->sigma_t_prime, theta, r,
                              phi, &value),
            "bssrdf_table_eval");
    *out_full = value / pdf_area;
}

int main(int argc, char **argv) {
    bssrdf_library *library = NULL;
    bssrdf_channel *green = NULL;
    bssrdf_channel_info info;
    medium m;
    double theta, rho_eff, sum[2] = {0.0, 0.0}, sum2[2] = {0.0, 0.0};
    long draws = 100000, k;
    uint64_t rng = 2026;
    int j;
    if (argc < 4 || argc > 5) {
        fprintf(stderr, "usage: %s LIBRARY_FILE MATERIAL THETA_DEGREES [DRAWS]\n", argv[0]);
        return 2;
    }
    theta = atof(argv[3]) * (TWO_PI / 360.0);
    if (argc == 5) {
        draws = atol(argv[4]);
    }
    if (draws < 2) {
        fprintf(stderr, "DRAWS must be at least 2\n");
        return 2;
    }
    require(bssrdf_library_open(argv[1], BSSRDF_OPEN_MAP, &library), "bssrdf_library_open");
    /* The medium of the shading point: here the green channel of MATERIAL; a textured
     * renderer passes its own rho' and sigma_t' per point */
    require(bssrdf_library_channel(library, argv[2], 1, &green), "bssrdf_library_channel");
    require(bssrdf_channel_get_info(green, &info), "bssrdf_channel_get_info");
    m.library = library;
    m.table = info.table;
    m.rho_prime = info.rho_prime;
    m.sigma_t_prime = info.sigma_t_prime;
    require(bssrdf_table_effective_albedo(library, m.table, m.rho_prime, m.sigma_t_prime, theta,
                                          &rho_eff),
            "bssrdf_table_effective_albedo");
    for (k = 0; k < draws; k++) {
        double w[2];
        /* The renderer's tangent frame turns from point to point */
        shading_step(&m, theta, rho_eff, 0.7 * (double)(k % 9), &rng, &w[0], &w[1]);
        for (j = 0; j < 2; j++) {
            sum[j] += w[j];
            sum2[j] += w[j] * w[j];
        }
    }
    printf("%s, green channel: rho' = %.6g, sigma_t' = %.6g mm^-1, theta = %s degrees\n",
           argv[2], m.rho_prime, m.sigma_t_prime, argv[3]);
    printf("rho_eff(theta) = %.9g (bssrdf_table_effective_albedo)\n", rho_eff);
    for (j = 0; j < 2; j++) {
        const char *kind = j == 0 ? "separable" : "full";
        double mean = sum[j] / (double)draws;
        double var = (sum2[j] - (double)draws * mean * mean) / (double)(draws - 1);
        double error = sqrt(var > 0.0 ? var / (double)draws : 0.0);
        printf("%s weight: mean %.9g, standard error %.3g, %ld draws\n", kind, mean, error,
               draws);
        /* Machine-readable: the test reads these */
        printf("result %s %.17g %.17g %.17g\n", kind, rho_eff, mean, error);
    }
    bssrdf_channel_release(green);
    bssrdf_library_close(library);
    return 0;
}

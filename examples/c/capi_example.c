/*
 * capi_example: a renderer's use of the bssrdf-zoo C interface. Opens a library file made by
 * `bssrdf bake`, lists its materials, makes the lookup handles of one material's three
 * colour channels, and evaluates, samples and integrates them as a renderer would.
 *
 *   cargo build --release -p bssrdf-capi
 *   cc -std=c99 -O2 -I include examples/c/capi_example.c target/release/libbssrdf.a \
 *      -lpthread -ldl -lm -o capi_example          # Linux; macOS needs no extra -l flags
 *   ./capi_example scene.bssrdf [MATERIAL]
 *
 * Or link the shared library: ... -Ltarget/release -lbssrdf, run with
 * LD_LIBRARY_PATH=target/release.
 */
#include <math.h>
#include <stdio.h>

#include "bssrdf_zoo.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Prints the failure of `status` and returns 1, or returns 0 for success. */
static int failed(int status, const char *what) {
    if (status == BSSRDF_OK) {
        return 0;
    }
    fprintf(stderr, "%s: %s: %s\n", what, bssrdf_status_name(status), bssrdf_last_error_message());
    return 1;
}

int main(int argc, char **argv) {
    bssrdf_library *library = NULL;
    bssrdf_channel *rgb[3] = {NULL, NULL, NULL};
    const char *material = NULL;
    size_t count = 0, k;
    int c, exit_code = 1;
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: %s LIBRARY_FILE [MATERIAL]\n", argv[0]);
        return 2;
    }

    /* Once, at scene load: open (mapped), list materials, make the channels. */
    if (failed(bssrdf_library_open(argv[1], BSSRDF_OPEN_MAP, &library), "open")) {
        return 1;
    }
    if (failed(bssrdf_library_material_count(library, &count), "materials")) {
        goto done;
    }
    printf("%s: %lu material(s)\n", argv[1], (unsigned long)count);
    for (k = 0; k < count; k++) {
        const char *name = NULL;
        if (failed(bssrdf_library_material_name(library, k, &name), "material name")) {
            goto done;
        }
        printf("  %s\n", name);
        if (k == 0) {
            material = name; /* owned by the library: valid until it is closed */
        }
    }
    if (argc == 3) {
        material = argv[2];
    }
    if (material == NULL) {
        fprintf(stderr, "the library has no materials\n");
        goto done;
    }
    for (c = 0; c < 3; c++) {
        if (failed(bssrdf_library_channel(library, material, c, &rgb[c]), "channel")) {
            goto done;
        }
    }
    /* Channels keep the file open: the library handle is no longer needed. Copy what we
     * print later first, since the name belongs to the library. */
    printf("material %s\n", material);
    bssrdf_library_close(library);
    library = NULL;
    material = NULL;

    for (c = 0; c < 3; c++) {
        bssrdf_channel_info info;
        double theta_deg;
        if (failed(bssrdf_channel_get_info(rgb[c], &info), "info")) {
            goto done;
        }
        printf("channel %c: rho' = %.4f, sigma_t' = %.4f /mm, eta = %.3f (table %lu)\n",
               "rgb"[c], info.rho_prime, info.sigma_t_prime, info.eta, (unsigned long)info.table);
        for (theta_deg = 0.0; theta_deg <= 60.0; theta_deg += 60.0) {
            double theta = theta_deg * M_PI / 180.0, albedo = 0.0, fwd = 0.0, back = 0.0;
            bssrdf_sample s;
            double u[4] = {0.5, 0.25, 0.75, 0.1};
            bssrdf_path_sample p;
            /* Per shading point: S_p at r = 1 mm forward and backward, and its integral. */
            if (failed(bssrdf_channel_eval(rgb[c], theta, 1.0, 0.0, &fwd), "eval") ||
                failed(bssrdf_channel_eval(rgb[c], theta, 1.0, M_PI, &back), "eval") ||
                failed(bssrdf_channel_effective_albedo(rgb[c], theta, &albedo), "albedo")) {
                goto done;
            }
            printf("  theta %2.0f deg: S(1 mm, fwd) = %.6g /mm^2, S(1 mm, back) = %.6g /mm^2, "
                   "rho_eff = %.5f\n",
                   theta_deg, fwd, back, albedo);
            /* Importance sampling: the exit point and its density per mm^2. */
            if (bssrdf_channel_sample(rgb[c], theta, 0.5, 0.25, &s) == BSSRDF_OK) {
                printf("    sample: r = %.5f mm, phi = %+.4f rad, pdf = %.6g /mm^2\n", s.r, s.phi,
                       s.pdf);
            } else {
                printf("    no sample: %s\n", bssrdf_last_error_message());
            }
            if (theta_deg == 0.0 && bssrdf_channel_sample_path(rgb[c], u, &p) == BSSRDF_OK) {
                printf("    path sample: theta = %.4f rad, r = %.5f mm, pdf = %.6g\n", p.theta,
                       p.r, p.pdf);
            }
        }
    }
    exit_code = 0;
done:
    for (c = 0; c < 3; c++) {
        bssrdf_channel_release(rgb[c]);
    }
    bssrdf_library_close(library);
    return exit_code;
}

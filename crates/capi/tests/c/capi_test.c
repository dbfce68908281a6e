/*
 * capi_test: the C interface of bssrdf-zoo, driven from C. Run by
 * crates/capi/tests/capi/c_program.rs, which builds libbssrdf.a, bakes a library file and
 * writes the values the Rust API computes for it into an expectations file; this program recomputes each one through the C
 * interface and requires the same status and the same bits (the C interface returns the
 * doubles of the same Rust code, so equality is exact).
 *
 *   capi_test LIBRARY_FILE EXPECTATIONS_FILE [REFLECTANCE_EXPECTATIONS_FILE]
 *
 * Expectations, one per line, doubles as 16 hex digits of their IEEE-754 bits:
 *   M material channel status            make the current channel (status expected)
 *   I rho' sigma_t' eta table            bssrdf_channel_get_info
 *   E theta r phi status value           bssrdf_channel_eval
 *   P theta r phi status pdf             bssrdf_channel_pdf
 *   S theta u_r u_phi status r phi pdf   bssrdf_channel_sample
 *   T u0 u1 u2 u3 status theta r phi phi' pdf_theta pdf   bssrdf_channel_sample_path
 *   Q theta status pdf_theta             bssrdf_channel_pdf_theta
 *   A theta status albedo                bssrdf_channel_effective_albedo
 *   X table rho' sigma_t' status         a medium the per-call lookups refuse
 *   D theta u status r pdf               bssrdf_channel_sample_radius
 *   W theta r status pdf                 bssrdf_channel_pdf_radius
 *   K theta r phi status factor          bssrdf_channel_angular_factor
 *   F theta status reflectance           bssrdf_channel_diffuse_reflectance
 * Values after a failing status are written as 0 and not compared; outputs must then be
 * untouched. Every channel lookup (E P S T Q A D W K F) is also made with the medium given per
 * call (bssrdf_table_*, the channel's rho', sigma_t' and table from its I line), which must
 * give the same status and bits; an X medium must fail every per-call lookup with its status.
 * At the end of each run, the points of every E, P, S, D, W, K and T line and of every X
 * medium (on a table of the file) go through the batch functions (bssrdf_table_*_n), table by
 * table, and each point must give the bits of its line, or 0 (every field of a draw) where the
 * line's status is a failure. The whole file is run for both open modes, the second time with the library
 * closed as soon as each channel is made (channels keep the file open; the per-call lookups
 * reopen it).
 *
 * The diffuse reflectance's functions read a file of their own (section "Diffuse
 * reflectance" below).
 *
 * Prints "ok: N checks" and exits 0, or prints each mismatch and exits 1 (2 for usage/IO).
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bssrdf_zoo.h"

static int failures = 0;
static long checks = 0;

/* The points of the batches: kind (the letter of the line: 'E', 'P', 'S', 'D', 'W', 'K' or
 * 'T'), the table, the medium, the arguments after the medium and the expected outputs (0
 * where the single call fails). */
#define MAX_POINTS 8192
#define MAX_ARGS 4
#define MAX_OUTPUTS 6
typedef struct point {
    char kind;
    size_t table;
    double rho, sigma_t;
    double args[MAX_ARGS];
    double want[MAX_OUTPUTS];
} point;
static point points[MAX_POINTS];
static size_t point_count = 0;

/* How many arguments (after the medium) and outputs the batch of a kind has. */
static int batch_args(char kind) {
    return kind == 'D' || kind == 'W' ? 2 : kind == 'T' ? 4 : 3;
}
static int batch_outputs(char kind) {
    return kind == 'S' ? 3 : kind == 'D' ? 2 : kind == 'T' ? 6 : 1;
}

static void add_point(char kind, size_t table, double rho, double sigma_t, const double *args,
                      int ok, const double *want) {
    point *p = &points[point_count];
    int k;
    if (point_count == MAX_POINTS) {
        fprintf(stderr, "more than %d batch points\n", MAX_POINTS);
        exit(2);
    }
    point_count++;
    p->kind = kind;
    p->table = table;
    p->rho = rho;
    p->sigma_t = sigma_t;
    for (k = 0; k < MAX_ARGS; k++) {
        p->args[k] = k < batch_args(kind) ? args[k] : 0.0;
    }
    for (k = 0; k < MAX_OUTPUTS; k++) {
        p->want[k] = ok && k < batch_outputs(kind) ? want[k] : 0.0;
    }
}

static void fail(int line, const char *what) {
    fprintf(stderr, "line %d: %s\n", line, what);
    failures++;
}

static int read_double(FILE *f, double *out) {
    char token[64];
    unsigned long long bits;
    if (fscanf(f, "%63s", token) != 1) {
        return 0;
    }
    bits = strtoull(token, NULL, 16);
    memcpy(out, &bits, sizeof *out);
    return 1;
}

static int read_doubles(FILE *f, double *out, int n) {
    int k;
    for (k = 0; k < n; k++) {
        if (!read_double(f, &out[k])) {
            return 0;
        }
    }
    return 1;
}

static void same_bits(int line, const char *what, double got, double want) {
    checks++;
    if (memcmp(&got, &want, sizeof got) != 0) {
        char message[160];
        sprintf(message, "%s: C gives %.17g, Rust %.17g", what, got, want);
        fail(line, message);
    }
}

static void same_status(int line, const char *what, int got, int want) {
    checks++;
    if (got != want) {
        char message[160];
        sprintf(message, "%s: status %s (%s), expected %s", what, bssrdf_status_name(got),
                got ? bssrdf_last_error_message() : "", bssrdf_status_name(want));
        fail(line, message);
    } else if (got != BSSRDF_OK && bssrdf_last_error_message()[0] == '\0') {
        fail(line, "a failure without a message");
    }
}

/* Statuses of the per-call lookups of a medium (0 where a status of the line is expected),
 * each compared with `want`. */
static void per_call_fails(int line, const bssrdf_library *library, size_t table, double rho,
                           double sigma_t, int want) {
    double out = -7.0, u[4] = {0.5, 0.5, 0.5, 0.5};
    bssrdf_sample s = {-7.0, -7.0, -7.0};
    bssrdf_path_sample p = {-7.0, -7.0, -7.0, -7.0, -7.0, -7.0};
    bssrdf_radial_sample d = {-7.0, -7.0};
    same_status(line, "table eval", bssrdf_table_eval(library, table, rho, sigma_t, 0.3, 0.5, 0.0, &out), want);
    same_status(line, "table pdf", bssrdf_table_pdf(library, table, rho, sigma_t, 0.3, 0.5, 0.0, &out), want);
    same_status(line, "table sample",
                bssrdf_table_sample(library, table, rho, sigma_t, 0.3, 0.5, 0.5, &s), want);
    same_status(line, "table sample_path",
                bssrdf_table_sample_path(library, table, rho, sigma_t, u, &p), want);
    same_status(line, "table pdf_theta",
                bssrdf_table_pdf_theta(library, table, rho, sigma_t, 0.3, &out), want);
    same_status(line, "table effective_albedo",
                bssrdf_table_effective_albedo(library, table, rho, sigma_t, 0.3, &out), want);
    same_status(line, "table sample_radius",
                bssrdf_table_sample_radius(library, table, rho, sigma_t, 0.3, 0.5, &d), want);
    same_status(line, "table pdf_radius",
                bssrdf_table_pdf_radius(library, table, rho, sigma_t, 0.3, 0.5, &out), want);
    same_status(line, "table angular_factor",
                bssrdf_table_angular_factor(library, table, rho, sigma_t, 0.3, 0.5, 0.0, &out),
                want);
    same_status(line, "table diffuse_reflectance",
                bssrdf_table_diffuse_reflectance(library, table, rho, sigma_t, 0.3, &out), want);
    same_bits(line, "untouched", out, -7.0);
    same_bits(line, "untouched radial", d.pdf, -7.0);
    same_bits(line, "untouched sample", s.pdf, -7.0);
    same_bits(line, "untouched path", p.pdf, -7.0);
}

/* The batch points of table `table` of one kind, through the batch function, against their
 * lines. */
static void run_batch(const bssrdf_library *library, size_t table, char kind) {
    static double rho[MAX_POINTS], sigma_t[MAX_POINTS], in[MAX_ARGS][MAX_POINTS],
        out[MAX_OUTPUTS][MAX_POINTS];
    static const char *const names[] = {"eval_n", "pdf_n", "sample_n", "sample_radius_n",
                                        "pdf_radius_n", "angular_factor_n", "sample_path_n"};
    const char *kinds = "EPSDWKT";
    const char *name = names[strchr(kinds, kind) - kinds];
    size_t n = 0, k;
    int j, status;
    for (k = 0; k < point_count; k++) {
        const point *p = &points[k];
        if (p->kind == kind && p->table == table) {
            rho[n] = p->rho;
            sigma_t[n] = p->sigma_t;
            for (j = 0; j < MAX_ARGS; j++) {
                in[j][n] = p->args[j];
            }
            for (j = 0; j < MAX_OUTPUTS; j++) {
                out[j][n] = -7.0;
            }
            n++;
        }
    }
    switch (kind) {
    case 'E':
        status = bssrdf_table_eval_n(library, table, n, rho, sigma_t, in[0], in[1], in[2], out[0]);
        break;
    case 'P':
        status = bssrdf_table_pdf_n(library, table, n, rho, sigma_t, in[0], in[1], in[2], out[0]);
        break;
    case 'S':
        status = bssrdf_table_sample_n(library, table, n, rho, sigma_t, in[0], in[1], in[2], out[0],
                                       out[1], out[2]);
        break;
    case 'D':
        status = bssrdf_table_sample_radius_n(library, table, n, rho, sigma_t, in[0], in[1], out[0],
                                              out[1]);
        break;
    case 'W':
        status = bssrdf_table_pdf_radius_n(library, table, n, rho, sigma_t, in[0], in[1], out[0]);
        break;
    case 'K':
        status = bssrdf_table_angular_factor_n(library, table, n, rho, sigma_t, in[0], in[1],
                                               in[2], out[0]);
        break;
    default:
        status = bssrdf_table_sample_path_n(library, table, n, rho, sigma_t, in[0], in[1], in[2],
                                            in[3], out[0], out[1], out[2], out[3], out[4], out[5]);
        break;
    }
    same_status(0, name, status, BSSRDF_OK);
    n = 0;
    for (k = 0; k < point_count; k++) {
        const point *p = &points[k];
        if (p->kind == kind && p->table == table) {
            for (j = 0; j < batch_outputs(kind); j++) {
                same_bits((int)k, name, out[j][n], p->want[j]);
            }
            n++;
        }
    }
}

/* The n fields of a draw, named by `names`, against `want`. */
static void same_fields(int line, const char *what, const char *const *names, const double *got,
                        const double *want, int n) {
    int k;
    for (k = 0; k < n; k++) {
        char name[64];
        sprintf(name, "%.40s %s", what, names[k]);
        same_bits(line, name, got[k], want[k]);
    }
}

/* A draw (r, phi, pdf) against `want`. */
static void same_sample(int line, const char *what, bssrdf_sample s, const double *want) {
    static const char *const names[3] = {"r", "phi", "pdf"};
    double got[3];
    got[0] = s.r;
    got[1] = s.phi;
    got[2] = s.pdf;
    same_fields(line, what, names, got, want, 3);
}

/* A path draw (theta, r, phi, phi', pdf_theta, pdf) against `want`. */
static void same_path(int line, const char *what, bssrdf_path_sample p, const double *want) {
    static const char *const names[6] = {"theta", "r", "phi", "phi'", "pdf_theta", "pdf"};
    double got[6];
    got[0] = p.theta;
    got[1] = p.r;
    got[2] = p.phi;
    got[3] = p.phi_prime;
    got[4] = p.pdf_theta;
    got[5] = p.pdf;
    same_fields(line, what, names, got, want, 6);
}

/* Runs the expectations file once; `close_early` closes the library right after each
 * channel is made. */
static void run(const char *library_path, const char *expectations, uint32_t flags,
                int close_early) {
    FILE *f = fopen(expectations, "r");
    bssrdf_library *library = NULL;
    bssrdf_channel *channel = NULL;
    bssrdf_channel_info info = {0.0, 0.0, 0.0, 0};
    char kind[4];
    int line = 0;
    size_t tables = 0, t;
    if (f == NULL) {
        perror(expectations);
        exit(2);
    }
    point_count = 0;
    while (fscanf(f, "%3s", kind) == 1) {
        double v[12];
        int status, want;
        line++;
        if (library == NULL) {
            status = bssrdf_library_open(library_path, flags, &library);
            same_status(line, "open", status, BSSRDF_OK);
            if (status != BSSRDF_OK) {
                exit(1);
            }
        }
        if (kind[0] == 'M') {
            char material[80];
            int rgb;
            if (fscanf(f, "%79s %d %d", material, &rgb, &want) != 3) {
                break;
            }
            bssrdf_channel_release(channel);
            channel = (bssrdf_channel *)&line; /* must become NULL on failure */
            status = bssrdf_library_channel(library, material, rgb, &channel);
            same_status(line, "channel", status, want);
            if (status != BSSRDF_OK && channel != NULL) {
                fail(line, "a failed channel call left a non-NULL handle");
                channel = NULL;
            }
            if (close_early) {
                bssrdf_library_close(library);
                library = NULL;
            }
        } else if (kind[0] == 'I') {
            if (!read_doubles(f, v, 4)) {
                break;
            }
            same_status(line, "info", bssrdf_channel_get_info(channel, &info), BSSRDF_OK);
            same_bits(line, "rho'", info.rho_prime, v[0]);
            same_bits(line, "sigma_t'", info.sigma_t_prime, v[1]);
            same_bits(line, "eta", info.eta, v[2]);
            same_bits(line, "table", (double)info.table, v[3]);
        } else if (kind[0] == 'X') {
            unsigned long table;
            if (fscanf(f, "%lu", &table) != 1 || !read_doubles(f, v, 2) ||
                fscanf(f, "%d", &want) != 1) {
                break;
            }
            per_call_fails(line, library, table, v[0], v[1], want);
            if (want != BSSRDF_ERROR_NOT_FOUND) {
                double args[4] = {0.3, 0.5, 0.0, 0.5}, none[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
                const char *kinds = "EPSDWKT";
                for (; *kinds != '\0'; kinds++) {
                    add_point(*kinds, table, v[0], v[1], args, 0, none);
                }
            }
        } else if (kind[0] == 'E' || kind[0] == 'P') {
            double out = -7.0, out2 = -7.0;
            int status2;
            if (!read_doubles(f, v, 3) || fscanf(f, "%d", &want) != 1 || !read_double(f, &v[3])) {
                break;
            }
            if (kind[0] == 'E') {
                status = bssrdf_channel_eval(channel, v[0], v[1], v[2], &out);
                status2 = bssrdf_table_eval(library, info.table, info.rho_prime,
                                            info.sigma_t_prime, v[0], v[1], v[2], &out2);
            } else {
                status = bssrdf_channel_pdf(channel, v[0], v[1], v[2], &out);
                status2 = bssrdf_table_pdf(library, info.table, info.rho_prime,
                                           info.sigma_t_prime, v[0], v[1], v[2], &out2);
            }
            same_status(line, kind[0] == 'E' ? "eval" : "pdf", status, want);
            same_bits(line, "value", out, status == BSSRDF_OK ? v[3] : -7.0);
            same_status(line, kind[0] == 'E' ? "table eval" : "table pdf", status2, want);
            same_bits(line, "table value", out2, status2 == BSSRDF_OK ? v[3] : -7.0);
            add_point(kind[0], info.table, info.rho_prime, info.sigma_t_prime, v,
                      want == BSSRDF_OK, &v[3]);
        } else if (kind[0] == 'S') {
            bssrdf_sample s = {-7.0, -7.0, -7.0}, s2 = {-7.0, -7.0, -7.0};
            if (!read_doubles(f, v, 3) || fscanf(f, "%d", &want) != 1 ||
                !read_doubles(f, v + 3, 3)) {
                break;
            }
            add_point('S', info.table, info.rho_prime, info.sigma_t_prime, v, want == BSSRDF_OK,
                      &v[3]);
            status = bssrdf_channel_sample(channel, v[0], v[1], v[2], &s);
            same_status(line, "sample", status, want);
            same_status(line, "table sample",
                        bssrdf_table_sample(library, info.table, info.rho_prime,
                                            info.sigma_t_prime, v[0], v[1], v[2], &s2),
                        want);
            if (status != BSSRDF_OK) {
                v[3] = v[4] = v[5] = -7.0;
            }
            same_sample(line, "sample", s, &v[3]);
            same_sample(line, "table sample", s2, &v[3]);
        } else if (kind[0] == 'T') {
            bssrdf_path_sample p = {-7.0, -7.0, -7.0, -7.0, -7.0, -7.0};
            bssrdf_path_sample p2 = {-7.0, -7.0, -7.0, -7.0, -7.0, -7.0};
            int k;
            if (!read_doubles(f, v, 4) || fscanf(f, "%d", &want) != 1 ||
                !read_doubles(f, v + 4, 6)) {
                break;
            }
            status = bssrdf_channel_sample_path(channel, v, &p);
            same_status(line, "sample_path", status, want);
            same_status(line, "table sample_path",
                        bssrdf_table_sample_path(library, info.table, info.rho_prime,
                                                 info.sigma_t_prime, v, &p2),
                        want);
            if (status != BSSRDF_OK) {
                for (k = 4; k < 10; k++) {
                    v[k] = -7.0;
                }
            }
            add_point('T', info.table, info.rho_prime, info.sigma_t_prime, v, want == BSSRDF_OK,
                      &v[4]);
            same_path(line, "path", p, &v[4]);
            same_path(line, "table path", p2, &v[4]);
        } else if (kind[0] == 'Q' || kind[0] == 'A') {
            double out = -7.0, out2 = -7.0;
            int status2;
            if (!read_double(f, &v[0]) || fscanf(f, "%d", &want) != 1 || !read_double(f, &v[1])) {
                break;
            }
            if (kind[0] == 'Q') {
                status = bssrdf_channel_pdf_theta(channel, v[0], &out);
                status2 = bssrdf_table_pdf_theta(library, info.table, info.rho_prime,
                                                 info.sigma_t_prime, v[0], &out2);
            } else {
                status = bssrdf_channel_effective_albedo(channel, v[0], &out);
                status2 = bssrdf_table_effective_albedo(library, info.table, info.rho_prime,
                                                        info.sigma_t_prime, v[0], &out2);
            }
            same_status(line, kind[0] == 'Q' ? "pdf_theta" : "effective_albedo", status, want);
            same_bits(line, "value", out, status == BSSRDF_OK ? v[1] : -7.0);
            same_status(line, "table lookup", status2, want);
            same_bits(line, "table value", out2, status2 == BSSRDF_OK ? v[1] : -7.0);
        } else if (kind[0] == 'D') {
            bssrdf_radial_sample d = {-7.0, -7.0}, d2 = {-7.0, -7.0};
            if (!read_doubles(f, v, 2) || fscanf(f, "%d", &want) != 1 ||
                !read_doubles(f, v + 2, 2)) {
                break;
            }
            add_point('D', info.table, info.rho_prime, info.sigma_t_prime, v, want == BSSRDF_OK,
                      &v[2]);
            status = bssrdf_channel_sample_radius(channel, v[0], v[1], &d);
            same_status(line, "sample_radius", status, want);
            same_status(line, "table sample_radius",
                        bssrdf_table_sample_radius(library, info.table, info.rho_prime,
                                                   info.sigma_t_prime, v[0], v[1], &d2),
                        want);
            if (status != BSSRDF_OK) {
                v[2] = v[3] = -7.0;
            }
            same_bits(line, "radial r", d.r, v[2]);
            same_bits(line, "radial pdf", d.pdf, v[3]);
            same_bits(line, "table radial r", d2.r, v[2]);
            same_bits(line, "table radial pdf", d2.pdf, v[3]);
        } else if (kind[0] == 'W' || kind[0] == 'K' || kind[0] == 'F') {
            int n_args = kind[0] == 'W' ? 2 : kind[0] == 'K' ? 3 : 1;
            double out = -7.0, out2 = -7.0;
            int status2;
            if (!read_doubles(f, v, n_args) || fscanf(f, "%d", &want) != 1 ||
                !read_double(f, &v[n_args])) {
                break;
            }
            if (kind[0] == 'W') {
                status = bssrdf_channel_pdf_radius(channel, v[0], v[1], &out);
                status2 = bssrdf_table_pdf_radius(library, info.table, info.rho_prime,
                                                  info.sigma_t_prime, v[0], v[1], &out2);
            } else if (kind[0] == 'K') {
                status = bssrdf_channel_angular_factor(channel, v[0], v[1], v[2], &out);
                status2 = bssrdf_table_angular_factor(library, info.table, info.rho_prime,
                                                      info.sigma_t_prime, v[0], v[1], v[2],
                                                      &out2);
            } else {
                status = bssrdf_channel_diffuse_reflectance(channel, v[0], &out);
                status2 = bssrdf_table_diffuse_reflectance(library, info.table, info.rho_prime,
                                                           info.sigma_t_prime, v[0], &out2);
            }
            if (kind[0] != 'F') {
                add_point(kind[0], info.table, info.rho_prime, info.sigma_t_prime, v,
                          want == BSSRDF_OK, &v[n_args]);
            }
            same_status(line, kind[0] == 'W' ? "pdf_radius" : kind[0] == 'K' ? "angular_factor"
                                                                             : "reflectance",
                        status, want);
            same_bits(line, "value", out, status == BSSRDF_OK ? v[n_args] : -7.0);
            same_status(line, "table lookup", status2, want);
            same_bits(line, "table value", out2, status2 == BSSRDF_OK ? v[n_args] : -7.0);
        } else {
            fail(line, "unknown expectation kind");
            break;
        }
    }
    if (!feof(f)) {
        fail(line, "malformed expectations file");
    }
    fclose(f);
    if (library == NULL) {
        same_status(line, "open", bssrdf_library_open(library_path, flags, &library), BSSRDF_OK);
    }
    same_status(line, "tables", bssrdf_library_table_count(library, &tables), BSSRDF_OK);
    for (t = 0; t < tables; t++) {
        const char *kinds = "EPSDWKT";
        for (; *kinds != '\0'; kinds++) {
            run_batch(library, t, *kinds);
        }
    }
    bssrdf_channel_release(channel);
    bssrdf_library_close(library);
}

/* NULL pointers, a missing file, unknown flags and names: codes and messages. */
static void boundary_checks(const char *library_path) {
    bssrdf_library *library = NULL;
    bssrdf_channel *channel = NULL;
    size_t count = 99;
    const char *name = NULL;
    double value = -7.0;
    same_status(0, "NULL path", bssrdf_library_open(NULL, 0, &library), BSSRDF_ERROR_NULL_POINTER);
    same_status(0, "missing file",
                bssrdf_library_open("/no/such/file.bssrdf", BSSRDF_OPEN_READ, &library),
                BSSRDF_ERROR_IO);
    if (strstr(bssrdf_last_error_message(), "/no/such/file.bssrdf") == NULL) {
        fail(0, "the I/O message does not name the file");
    }
    same_status(0, "flags", bssrdf_library_open(library_path, 8u, &library),
                BSSRDF_ERROR_INVALID_ARGUMENT);
    same_status(0, "open", bssrdf_library_open(library_path, BSSRDF_OPEN_MAP, &library), BSSRDF_OK);
    same_status(0, "NULL out_count", bssrdf_library_table_count(library, NULL),
                BSSRDF_ERROR_NULL_POINTER);
    same_status(0, "tables", bssrdf_library_table_count(library, &count), BSSRDF_OK);
    {
        /* The fixture's tables are PBD's: no walk, so no g (NaN) and component 0 */
        bssrdf_table_info info;
        same_status(0, "table info", bssrdf_library_table_info(library, 0, &info), BSSRDF_OK);
        if (info.model != BSSRDF_MODEL_PBD_ANGULAR || info.walk_component != 0 ||
            info.walk_g == info.walk_g || !(info.eta > 0.0)) {
            fail(0, "table 0's info is not a PBD table's");
        }
        same_status(0, "table info past the end",
                    bssrdf_library_table_info(library, count, &info), BSSRDF_ERROR_NOT_FOUND);
        same_status(0, "NULL out_info", bssrdf_library_table_info(library, 0, NULL),
                    BSSRDF_ERROR_NULL_POINTER);
    }
    same_status(0, "materials", bssrdf_library_material_count(library, &count), BSSRDF_OK);
    same_status(0, "name", bssrdf_library_material_name(library, 0, &name), BSSRDF_OK);
    same_status(0, "name past the end", bssrdf_library_material_name(library, count, &name),
                BSSRDF_ERROR_NOT_FOUND);
    same_status(0, "NULL material", bssrdf_library_channel(library, NULL, 0, &channel),
                BSSRDF_ERROR_NULL_POINTER);
    if (strcmp(bssrdf_last_error_message(), "material is NULL") != 0) {
        fail(0, "the NULL material message is not 'material is NULL'");
    }
    same_status(0, "channel 3", bssrdf_library_channel(library, name, 3, &channel),
                BSSRDF_ERROR_INVALID_ARGUMENT);
    same_status(0, "medium", bssrdf_library_medium(library, 0, 0.5, 2.0, &channel), BSSRDF_OK);
    same_status(0, "NULL out_value", bssrdf_channel_eval(channel, 0.1, 1.0, 0.0, NULL),
                BSSRDF_ERROR_NULL_POINTER);
    same_status(0, "NULL channel", bssrdf_channel_eval(NULL, 0.1, 1.0, 0.0, &value),
                BSSRDF_ERROR_NULL_POINTER);
    same_bits(0, "untouched output", value, -7.0);
    {
        double in[2] = {0.5, 0.5}, out[3] = {-7.0, -7.0, -7.0};
        same_status(0, "NULL batch array",
                    bssrdf_table_eval_n(library, 0, 2, in, in, NULL, in, in, out),
                    BSSRDF_ERROR_NULL_POINTER);
        if (strstr(bssrdf_last_error_message(), "theta is NULL") == NULL) {
            fail(0, "the NULL message does not name the array");
        }
        same_status(0, "overlapping batch output",
                    bssrdf_table_sample_n(library, 0, 2, in, in, in, in, in, out, out + 1,
                                          in),
                    BSSRDF_ERROR_INVALID_ARGUMENT);
        same_bits(0, "untouched batch output", out[0], -7.0);
        same_status(0, "batch of none", bssrdf_table_pdf_n(library, 0, 0, in, in, in, in, in, out),
                    BSSRDF_OK);
        same_status(0, "medium out of range",
                    bssrdf_table_eval(library, 0, 1.5, 2.0, 0.1, 1.0, 0.0, &value),
                    BSSRDF_ERROR_OUT_OF_RANGE);
        if (strstr(bssrdf_last_error_message(), "rho' = 1.5") == NULL) {
            fail(0, "the medium's message does not name the value");
        }
    }
    bssrdf_channel_release(channel);
    bssrdf_library_close(library);
    bssrdf_channel_release(NULL);
    bssrdf_library_close(NULL);
}

/* Every declared function, with its declared type: the program links only if the library
 * exports each of them. */
typedef void (*any_function)(void);
static const any_function every_function[] = {
    (any_function)bssrdf_library_open,           (any_function)bssrdf_library_close,
    (any_function)bssrdf_library_table_count,    (any_function)bssrdf_library_table_info,
    (any_function)bssrdf_library_material_count,
    (any_function)bssrdf_library_material_name,  (any_function)bssrdf_library_channel,
    (any_function)bssrdf_library_medium,         (any_function)bssrdf_channel_release,
    (any_function)bssrdf_channel_get_info,       (any_function)bssrdf_channel_eval,
    (any_function)bssrdf_channel_pdf,            (any_function)bssrdf_channel_sample,
    (any_function)bssrdf_channel_sample_path,    (any_function)bssrdf_channel_pdf_theta,
    (any_function)bssrdf_channel_effective_albedo, (any_function)bssrdf_table_eval,
    (any_function)bssrdf_table_pdf,              (any_function)bssrdf_table_sample,
    (any_function)bssrdf_table_sample_path,      (any_function)bssrdf_table_pdf_theta,
    (any_function)bssrdf_table_effective_albedo, (any_function)bssrdf_table_eval_n,
    (any_function)bssrdf_table_pdf_n,            (any_function)bssrdf_table_sample_n,
    (any_function)bssrdf_table_sample_radius,    (any_function)bssrdf_table_pdf_radius,
    (any_function)bssrdf_table_angular_factor,   (any_function)bssrdf_channel_sample_radius,
    (any_function)bssrdf_channel_pdf_radius,     (any_function)bssrdf_channel_angular_factor,
    (any_function)bssrdf_table_sample_radius_n,  (any_function)bssrdf_table_pdf_radius_n,
    (any_function)bssrdf_table_angular_factor_n, (any_function)bssrdf_table_sample_path_n,
    (any_function)bssrdf_channel_diffuse_reflectance,
    (any_function)bssrdf_table_diffuse_reflectance,
    (any_function)bssrdf_last_error_message,     (any_function)bssrdf_status_name,
};

/* ---- Diffuse reflectance: bssrdf_library_reflectance_range, bssrdf_library_invert_albedo.
 * Expectations, one per line, doubles as 16 hex digits of their IEEE-754 bits:
 *   G table theta status min max             bssrdf_library_reflectance_range
 *   R table reflectance theta status rho'    bssrdf_library_invert_albedo
 * Values after a failing status are written as 0 and not compared; outputs must then be
 * untouched. */
static const any_function reflectance_functions[] = {
    (any_function)bssrdf_library_reflectance_range,
    (any_function)bssrdf_library_invert_albedo,
};

/* A double from the 16 hex digits of its bits. */
static double from_bits(const char *hex) {
    unsigned long long bits = strtoull(hex, NULL, 16);
    double out;
    memcpy(&out, &bits, sizeof out);
    return out;
}

static void reflectance_checks(const char *library_path, const char *expectations,
                               uint32_t flags) {
    FILE *f = fopen(expectations, "r");
    bssrdf_library *library = NULL;
    char text[256], a[24], b[24], c[24];
    int line = 0;
    size_t k;
    for (k = 0; k < sizeof reflectance_functions / sizeof reflectance_functions[0]; k++) {
        if (reflectance_functions[k] == NULL) {
            fail(0, "a function resolved to NULL");
        }
    }
    if (f == NULL) {
        perror(expectations);
        exit(2);
    }
    same_status(0, "open", bssrdf_library_open(library_path, flags, &library), BSSRDF_OK);
    /* One expectation per line, parsed whole. */
    while (library != NULL && fgets(text, sizeof text, f) != NULL) {
        unsigned long table;
        int want, status;
        double lo = -7.0, hi = -7.0, rho = -7.0;
        line++;
        if (sscanf(text, "G %lu %23s %d %23s %23s", &table, a, &want, b, c) == 5) {
            status = bssrdf_library_reflectance_range(library, (size_t)table, from_bits(a), &lo,
                                                      &hi);
            same_status(line, "reflectance_range", status, want);
            same_bits(line, "min", lo, status == BSSRDF_OK ? from_bits(b) : -7.0);
            same_bits(line, "max", hi, status == BSSRDF_OK ? from_bits(c) : -7.0);
        } else if (sscanf(text, "R %lu %23s %23s %d %23s", &table, a, b, &want, c) == 5) {
            status = bssrdf_library_invert_albedo(library, (size_t)table, from_bits(a),
                                                  from_bits(b), &rho);
            same_status(line, "invert_albedo", status, want);
            same_bits(line, "rho'", rho, status == BSSRDF_OK ? from_bits(c) : -7.0);
        } else {
            fail(line, "malformed reflectance expectation");
        }
    }
    if (line == 0) {
        fail(0, "no reflectance expectations");
    }
    fclose(f);
    bssrdf_library_close(library);
}

int main(int argc, char **argv) {
    size_t k;
    if (argc != 3 && argc != 4) {
        fprintf(stderr, "usage: %s LIBRARY_FILE EXPECTATIONS_FILE [REFLECTANCE_EXPECTATIONS_FILE]\n",
                argv[0]);
        return 2;
    }
    for (k = 0; k < sizeof every_function / sizeof every_function[0]; k++) {
        if (every_function[k] == NULL) {
            fail(0, "a function resolved to NULL");
        }
    }
    boundary_checks(argv[1]);
    run(argv[1], argv[2], BSSRDF_OPEN_MAP, 0);
    run(argv[1], argv[2], BSSRDF_OPEN_READ, 1);
    if (argc == 4) {
        reflectance_checks(argv[1], argv[3], BSSRDF_OPEN_MAP);
        reflectance_checks(argv[1], argv[3], BSSRDF_OPEN_READ);
    }
    if (failures != 0) {
        fprintf(stderr, "%d of %ld checks failed\n", failures, checks);
        return 1;
    }
    printf("ok: %ld checks\n", checks);
    return 0;
}

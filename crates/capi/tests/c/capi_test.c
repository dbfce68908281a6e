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
 * Values after a failing status are written as 0 and not compared; outputs must then be
 * untouched. The whole file is run for both open modes, the second time with the library
 * closed as soon as each channel is made (channels keep the file open).
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

/* Runs the expectations file once; `close_early` closes the library right after each
 * channel is made. */
static void run(const char *library_path, const char *expectations, uint32_t flags,
                int close_early) {
    FILE *f = fopen(expectations, "r");
    bssrdf_library *library = NULL;
    bssrdf_channel *channel = NULL;
    char kind[4];
    int line = 0;
    if (f == NULL) {
        perror(expectations);
        exit(2);
    }
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
            bssrdf_channel_info info;
            if (!read_doubles(f, v, 4)) {
                break;
            }
            same_status(line, "info", bssrdf_channel_get_info(channel, &info), BSSRDF_OK);
            same_bits(line, "rho'", info.rho_prime, v[0]);
            same_bits(line, "sigma_t'", info.sigma_t_prime, v[1]);
            same_bits(line, "eta", info.eta, v[2]);
            same_bits(line, "table", (double)info.table, v[3]);
        } else if (kind[0] == 'E' || kind[0] == 'P') {
            double out = -7.0;
            if (!read_doubles(f, v, 3) || fscanf(f, "%d", &want) != 1 || !read_double(f, &v[3])) {
                break;
            }
            status = kind[0] == 'E' ? bssrdf_channel_eval(channel, v[0], v[1], v[2], &out)
                                    : bssrdf_channel_pdf(channel, v[0], v[1], v[2], &out);
            same_status(line, kind[0] == 'E' ? "eval" : "pdf", status, want);
            same_bits(line, "value", out, status == BSSRDF_OK ? v[3] : -7.0);
        } else if (kind[0] == 'S') {
            bssrdf_sample s = {-7.0, -7.0, -7.0};
            if (!read_doubles(f, v, 3) || fscanf(f, "%d", &want) != 1 ||
                !read_doubles(f, v + 3, 3)) {
                break;
            }
            status = bssrdf_channel_sample(channel, v[0], v[1], v[2], &s);
            same_status(line, "sample", status, want);
            if (status != BSSRDF_OK) {
                v[3] = v[4] = v[5] = -7.0;
            }
            same_bits(line, "sample r", s.r, v[3]);
            same_bits(line, "sample phi", s.phi, v[4]);
            same_bits(line, "sample pdf", s.pdf, v[5]);
        } else if (kind[0] == 'T') {
            bssrdf_path_sample p = {-7.0, -7.0, -7.0, -7.0, -7.0, -7.0};
            int k;
            if (!read_doubles(f, v, 4) || fscanf(f, "%d", &want) != 1 ||
                !read_doubles(f, v + 4, 6)) {
                break;
            }
            status = bssrdf_channel_sample_path(channel, v, &p);
            same_status(line, "sample_path", status, want);
            if (status != BSSRDF_OK) {
                for (k = 4; k < 10; k++) {
                    v[k] = -7.0;
                }
            }
            same_bits(line, "path theta", p.theta, v[4]);
            same_bits(line, "path r", p.r, v[5]);
            same_bits(line, "path phi", p.phi, v[6]);
            same_bits(line, "path phi'", p.phi_prime, v[7]);
            same_bits(line, "path pdf_theta", p.pdf_theta, v[8]);
            same_bits(line, "path pdf", p.pdf, v[9]);
        } else if (kind[0] == 'Q' || kind[0] == 'A') {
            double out = -7.0;
            if (!read_double(f, &v[0]) || fscanf(f, "%d", &want) != 1 || !read_double(f, &v[1])) {
                break;
            }
            status = kind[0] == 'Q' ? bssrdf_channel_pdf_theta(channel, v[0], &out)
                                    : bssrdf_channel_effective_albedo(channel, v[0], &out);
            same_status(line, kind[0] == 'Q' ? "pdf_theta" : "effective_albedo", status, want);
            same_bits(line, "value", out, status == BSSRDF_OK ? v[1] : -7.0);
        } else {
            fail(line, "unknown expectation kind");
            break;
        }
    }
    if (!feof(f)) {
        fail(line, "malformed expectations file");
    }
    fclose(f);
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
    same_status(0, "materials", bssrdf_library_material_count(library, &count), BSSRDF_OK);
    same_status(0, "name", bssrdf_library_material_name(library, 0, &name), BSSRDF_OK);
    same_status(0, "name past the end", bssrdf_library_material_name(library, count, &name),
                BSSRDF_ERROR_NOT_FOUND);
    same_status(0, "NULL material", bssrdf_library_channel(library, NULL, 0, &channel),
                BSSRDF_ERROR_NULL_POINTER);
    same_status(0, "channel 3", bssrdf_library_channel(library, name, 3, &channel),
                BSSRDF_ERROR_INVALID_ARGUMENT);
    same_status(0, "medium", bssrdf_library_medium(library, 0, 0.5, 2.0, &channel), BSSRDF_OK);
    same_status(0, "NULL out_value", bssrdf_channel_eval(channel, 0.1, 1.0, 0.0, NULL),
                BSSRDF_ERROR_NULL_POINTER);
    same_status(0, "NULL channel", bssrdf_channel_eval(NULL, 0.1, 1.0, 0.0, &value),
                BSSRDF_ERROR_NULL_POINTER);
    same_bits(0, "untouched output", value, -7.0);
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
    (any_function)bssrdf_library_table_count,    (any_function)bssrdf_library_material_count,
    (any_function)bssrdf_library_material_name,  (any_function)bssrdf_library_channel,
    (any_function)bssrdf_library_medium,         (any_function)bssrdf_channel_release,
    (any_function)bssrdf_channel_get_info,       (any_function)bssrdf_channel_eval,
    (any_function)bssrdf_channel_pdf,            (any_function)bssrdf_channel_sample,
    (any_function)bssrdf_channel_sample_path,    (any_function)bssrdf_channel_pdf_theta,
    (any_function)bssrdf_channel_effective_albedo, (any_function)bssrdf_last_error_message,
    (any_function)bssrdf_status_name,
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

/*
 * bssrdf_zoo.h: the C interface of bssrdf-zoo, tabulated BSSRDFs for rendering.
 *
 * Open a library file made by `bssrdf bake`, make one lookup handle per medium and colour
 * channel, then evaluate and sample S_p(r, phi; theta) at render time. Or, for media that
 * change from point to point (textures) or per wavelength, give the medium's rho' and
 * sigma_t' with every call (bssrdf_table_*) or with every point of a batch (bssrdf_table_*_n):
 * one table serves every medium of its eta.
 *
 * Build and link: `cargo build --release -p bssrdf-capi` makes target/release/libbssrdf.a (static;
 * link also -lpthread -ldl -lm on Linux) and libbssrdf.so (shared). Declarations here are
 * checked against the Rust exports by crates/capi/tests/capi/header.rs.
 *
 * Units: coefficients in mm^-1, distances in mm, S and densities per mm^2, angles in radians.
 * theta is the incidence angle from the normal BEFORE refraction, in [0, pi/2]; a table takes
 * the range of its f32 theta axis widened by half an f32 step at each end (at pi/2: the node
 * pi/2 + 4.4e-8, then up to pi/2 + 1.4e-7 as the node; beyond, refused). The exit point
 * lies at polar coordinates (r, phi) around the entry point, phi = 0 forward: in the plane of
 * incidence, on the side the refracted beam travels to. S_p is multiple scattering per unit
 * area per unit power entering the medium (no entry Fresnel factor).
 *
 * Errors: every function except the release and message functions returns a status,
 * BSSRDF_OK (0) or a BSSRDF_ERROR_* code. On failure, bssrdf_last_error_message() describes
 * the error; the message is per thread (thread-local) and stays valid until the next failing
 * call on the same thread. Successful calls do not touch it and do not allocate. Outputs are
 * written only on success, except handle outputs, which are set to NULL on failure.
 * Every pointer argument is checked: NULL gives BSSRDF_ERROR_NULL_POINTER. No Rust panic
 * crosses into C: a panic (a bug) is caught and gives BSSRDF_ERROR_PANIC.
 *
 * Ownership: bssrdf_library_open creates a library handle, which the caller owns and frees
 * with bssrdf_library_close. bssrdf_library_channel and bssrdf_library_medium create channel
 * handles, which the caller owns and frees with bssrdf_channel_release. A channel keeps the
 * library's file open by itself: the library may be closed before its channels (the file is
 * unmapped when the last handle goes). Strings returned by the library (material names)
 * are owned by the library handle; status names are static.
 *
 * Media per call: the bssrdf_table_* functions take the table's index and the medium's
 * reduced albedo rho' (within the table's albedo rows) and reduced extinction sigma_t' (mm^-1,
 * in [1e-9, 1e12]) with each lookup, check them as bssrdf_library_medium does (rho' outside
 * the rows or NaN: BSSRDF_ERROR_OUT_OF_RANGE; sigma_t' outside its range or NaN:
 * BSSRDF_ERROR_INVALID_ARGUMENT; the message names the value and its range), and return the
 * bits of a channel handle made for the same medium. They allocate nothing, failing or not.
 *
 * Batches: bssrdf_table_eval_n, _pdf_n, _sample_n, the separable renderers' _sample_radius_n,
 * _pdf_radius_n and _angular_factor_n, and the path-tracing draw _sample_path_n look up n points
 * given as structures of arrays (one array of n doubles per argument, one per output), each
 * point with its own medium, into output arrays. Point i gives the bits of the single call with
 * the i-th values. A point outside the domain does not fail the batch: its value or density is
 * 0 and its draw the failed draw, every field 0 (every successful draw has pdf > 0). The
 * call fails, writing nothing, for a NULL library or array (even with n = 0), an array not
 * aligned for a double, an output overlapping another array (inputs may overlap each other),
 * n too large to address, or an unknown table.
 *
 * Thread safety: handles are immutable. Any number of threads may call any function on the
 * same handle at the same time, except that closing or releasing a handle must not race with
 * any other use of that handle.
 *
 * Mapped files: another process truncating a mapped file kills the reader with SIGBUS; open
 * files that may change with BSSRDF_OPEN_READ.
 */
#ifndef BSSRDF_ZOO_H
#define BSSRDF_ZOO_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes. */
#define BSSRDF_OK 0
/* A pointer argument was NULL. */
#define BSSRDF_ERROR_NULL_POINTER 1
/* Unknown flag bits, a channel other than 0, 1, 2, a string that is not UTF-8, a medium with
 * sigma_t' outside [1e-9, 1e12] mm^-1 (or NaN), a batch's array misaligned or overlapping
 * an output, or n too large. */
#define BSSRDF_ERROR_INVALID_ARGUMENT 2
/* The operating system refused to open, map or read the file. */
#define BSSRDF_ERROR_IO 3
/* The file is not a valid library file (the message names the failed check), or a table of
 * it takes no lookups (the message says why). */
#define BSSRDF_ERROR_FORMAT 4
/* No material of that name, or no table or material of that index. */
#define BSSRDF_ERROR_NOT_FOUND 5
/* theta outside the table's theta axis (or NaN) in a lookup, or a medium's rho' outside the
 * table's albedo rows (or NaN) when a channel is made or in a per-call lookup. Tables are
 * never extrapolated. */
#define BSSRDF_ERROR_OUT_OF_RANGE 6
/* Nothing to sample: no energy stored (rho' = 0, light beyond the critical angle), theta
 * outside the table, a uniform outside [0, 1) (NaN and +-inf included: a broken random
 * stream), a radial uniform at 0 (the entry point) or at 1 (the last radius, where the
 * density is 0), or, for path sampling, a table baked without theta sampling. The message
 * names the cause. */
#define BSSRDF_ERROR_NO_SAMPLE 7
/* A bug: the library panicked and the panic was caught; the call did nothing. */
#define BSSRDF_ERROR_PANIC 8

/* Flags of bssrdf_library_open. */
/* Map the file read-only (the default). */
#define BSSRDF_OPEN_MAP 0u
/* Read the file into memory instead (for files that may change while open). */
#define BSSRDF_OPEN_READ 1u

/* An opened library file. Opaque. */
typedef struct bssrdf_library bssrdf_library;

/* The lookup handle of one medium (one colour channel of a material) on one table. Opaque. */
typedef struct bssrdf_channel bssrdf_channel;

/* One draw of the exit point. */
typedef struct bssrdf_sample {
    double r;   /* exit distance, mm */
    double phi; /* exit azimuth, radians in [-pi, pi], 0 forward */
    double pdf; /* density per mm^2 of the exit plane */
} bssrdf_sample;

/* One draw of the exit distance alone, for separable renderers. */
typedef struct bssrdf_radial_sample {
    double r;   /* exit distance, mm */
    double pdf; /* density per mm of the distance */
} bssrdf_radial_sample;

/* One path-tracing draw (Ferrier 2016, section 7.1, algorithm 3). */
typedef struct bssrdf_path_sample {
    double theta;     /* incidence before refraction, radians */
    double r;         /* exit distance, mm */
    double phi;       /* exit azimuth relative to the plane of incidence, radians */
    double phi_prime; /* azimuth of the entry point seen from the exit point, radians */
    double pdf_theta; /* density of theta, per radian */
    double pdf;       /* joint density: pdf_theta * pdf(r, phi | theta) / (2 pi) */
} bssrdf_path_sample;

/* What a channel handle looks up. */
typedef struct bssrdf_channel_info {
    double rho_prime;     /* reduced albedo sigma_s' / sigma_t' */
    double sigma_t_prime; /* reduced extinction sigma_s (1 - g) + sigma_a, mm^-1 */
    double eta;           /* relative index of refraction the table was baked for */
    size_t table;         /* index of the table in the file */
} bssrdf_channel_info;

/* What a table of a library tabulates. */
typedef struct bssrdf_table_info {
    double eta;              /* relative index of refraction the table was baked for */
    uint32_t model;          /* BSSRDF_MODEL_PBD_ANGULAR or BSSRDF_MODEL_WALK_ANGULAR */
    uint32_t walk_component; /* walk tables: BSSRDF_WALK_MULTIPLE or BSSRDF_WALK_TOTAL; else 0 */
    double walk_g;           /* walk tables: the Henyey-Greenstein g of the walk; else NaN */
} bssrdf_table_info;

/* bssrdf_table_info.model: photon beam diffusion tabulated (format model 1), or the Monte
 * Carlo walk tabulated for one g (format model 3, `bssrdf bake --source walk`). Both are
 * looked up alike. */
#define BSSRDF_MODEL_PBD_ANGULAR 1u
#define BSSRDF_MODEL_WALK_ANGULAR 3u
/* bssrdf_table_info.walk_component: multiple scattering, or everything that leaves. */
#define BSSRDF_WALK_MULTIPLE 0u
#define BSSRDF_WALK_TOTAL 1u

/* Opens the library file at `path` (NUL-terminated; any bytes on Unix, UTF-8 elsewhere) and
 * validates all of it (structure, checksums, every value finite). `flags` is BSSRDF_OPEN_MAP
 * or BSSRDF_OPEN_READ. Stores a new handle in *out_library (NULL on failure); free it with
 * bssrdf_library_close. A valid table no lookup can interpolate (one node on an axis, eta
 * outside [0.75, 2.5]) does not fail the open: the lookups on it fail with
 * BSSRDF_ERROR_FORMAT, the message saying why. */
int bssrdf_library_open(const char *path, uint32_t flags, bssrdf_library **out_library);

/* Frees a library handle; NULL does nothing. Channels made from it remain valid. */
void bssrdf_library_close(bssrdf_library *library);

/* Number of tables (one per eta baked). */
int bssrdf_library_table_count(const bssrdf_library *library, size_t *out_count);

/* What table `index` tabulates: eta, model, and for a walk-angular table its g and component.
 * BSSRDF_ERROR_NOT_FOUND for an index past the end. */
int bssrdf_library_table_info(const bssrdf_library *library, size_t index,
                              bssrdf_table_info *out_info);

/* Number of materials. */
int bssrdf_library_material_count(const bssrdf_library *library, size_t *out_count);

/* Name of material `index` (UTF-8, NUL-terminated), owned by the library: valid until it is
 * closed. BSSRDF_ERROR_NOT_FOUND for an index past the end. */
int bssrdf_library_material_name(const bssrdf_library *library, size_t index,
                                 const char **out_name);

/* The lookup handle of colour channel `channel` (0 red, 1 green, 2 blue) of the material
 * named `material`, in *out_channel (NULL on failure); free it with bssrdf_channel_release. */
int bssrdf_library_channel(const bssrdf_library *library, const char *material, int channel,
                           bssrdf_channel **out_channel);

/* The lookup handle of any medium on table `table`: reduced albedo rho_prime and reduced
 * extinction sigma_t_prime (mm^-1, in [1e-9, 1e12]), in *out_channel (NULL on failure). For
 * media that are not material records of the file; eta is the table's. */
int bssrdf_library_medium(const bssrdf_library *library, size_t table, double rho_prime,
                          double sigma_t_prime, bssrdf_channel **out_channel);

/* Frees a channel handle; NULL does nothing. */
void bssrdf_channel_release(bssrdf_channel *channel);

/* The channel's rho', sigma_t', eta and table index. */
int bssrdf_channel_get_info(const bssrdf_channel *channel, bssrdf_channel_info *out_info);

/* S_p(r, phi; theta) in mm^-2, r in mm: 0 beyond the table's last radius;
 * BSSRDF_ERROR_OUT_OF_RANGE for theta outside the table, r NaN, infinite or negative, or phi
 * not finite (the message names the value). */
int bssrdf_channel_eval(const bssrdf_channel *channel, double theta, double r_mm, double phi,
                        double *out_value);

/* Density per mm^2 of bssrdf_channel_sample at (r, phi): 0 where it cannot sample;
 * BSSRDF_ERROR_OUT_OF_RANGE at a point outside the domain of bssrdf_channel_eval. */
int bssrdf_channel_pdf(const bssrdf_channel *channel, double theta, double r_mm, double phi,
                       double *out_pdf);

/* Draws the exit point for incidence theta from two uniforms in [0, 1). The sample's pdf
 * is bssrdf_channel_pdf there to rounding (within 1e-13 relative; not always the same bits).
 * BSSRDF_ERROR_NO_SAMPLE where there is nothing to sample, and, on a table whose radii start at 0 (every baked one), for u_r = 0 (or below about
 * 1e-320), which draws the entry point itself (r = 0, where the density per area is
 * infinite): with uniforms of 53 bits, once in 2^53 draws. */
int bssrdf_channel_sample(const bssrdf_channel *channel, double theta, double u_r, double u_phi,
                          bssrdf_sample *out_sample);

/* The path-tracing draw from four uniforms u[0..3] in [0, 1): theta from the effective
 * albedo over theta, then (r, phi) given theta, then phi' uniform. BSSRDF_ERROR_NO_SAMPLE
 * without theta sampling in the table or where there is nothing to sample. */
int bssrdf_channel_sample_path(const bssrdf_channel *channel, const double *u,
                               bssrdf_path_sample *out_sample);

/* Density of theta in bssrdf_channel_sample_path, per radian (0 without theta sampling);
 * BSSRDF_ERROR_OUT_OF_RANGE for theta outside the table. */
int bssrdf_channel_pdf_theta(const bssrdf_channel *channel, double theta, double *out_pdf);

/* Effective albedo rho_eff(theta): multiply scattered power leaving per unit power entering
 * (dimensionless). BSSRDF_ERROR_OUT_OF_RANGE for theta outside the table. */
int bssrdf_channel_effective_albedo(const bssrdf_channel *channel, double theta,
                                    double *out_albedo);

/* For separable renderers (docs/embedding.md, "Separable renderers"): r drawn alone, phi by
 * the renderer (uniform), the point weighted by w = rho_eff(theta) * angular_factor, whose mean
 * is rho_eff(theta) exactly; or by w = S * 2 pi r / pdf_r with S from bssrdf_channel_eval.
 * The exit distance r in mm from one uniform u in [0, 1), with its density per mm: the radial
 * step of bssrdf_channel_sample (the same u gives the same r). BSSRDF_ERROR_NO_SAMPLE where
 * bssrdf_channel_sample fails with it. */
int bssrdf_channel_sample_radius(const bssrdf_channel *channel, double theta, double u,
                                 bssrdf_radial_sample *out_sample);

/* Density per mm of bssrdf_channel_sample_radius at r_mm (0 where it cannot sample);
 * BSSRDF_ERROR_OUT_OF_RANGE for theta outside the table or r NaN, infinite or negative. */
int bssrdf_channel_pdf_radius(const bssrdf_channel *channel, double theta, double r_mm,
                              double *out_pdf);

/* The angular factor S(r, phi; theta) / S_bar(r; theta), dimensionless, >= 0, with
 * S_bar = (1 / 2 pi) * integral of S over phi: bssrdf_channel_eval = S_bar * factor, and the
 * factor averages to 1 over phi. 0 beyond the table's last radius; BSSRDF_ERROR_OUT_OF_RANGE
 * for theta outside the table, r NaN, infinite or negative, or phi not finite. */
int bssrdf_channel_angular_factor(const bssrdf_channel *channel, double theta, double r_mm,
                                  double phi, double *out_factor);

/* Lookups with the medium given per call, on table `table` of an open library: rho_prime is
 * the reduced albedo sigma_s' / sigma_t', sigma_t_prime the reduced extinction in mm^-1. Each
 * is the bssrdf_channel_* function of the same name for a channel made with
 * bssrdf_library_medium(library, table, rho_prime, sigma_t_prime), with the same statuses and
 * bits, plus BSSRDF_ERROR_NOT_FOUND for an unknown table and the medium's own statuses. */

/* S_p(r, phi; theta) in mm^-2 (bssrdf_channel_eval). */
int bssrdf_table_eval(const bssrdf_library *library, size_t table, double rho_prime,
                      double sigma_t_prime, double theta, double r_mm, double phi,
                      double *out_value);

/* Density per mm^2 of bssrdf_table_sample at (r, phi) (bssrdf_channel_pdf). */
int bssrdf_table_pdf(const bssrdf_library *library, size_t table, double rho_prime,
                     double sigma_t_prime, double theta, double r_mm, double phi,
                     double *out_pdf);

/* Draws the exit point from two uniforms in [0, 1) (bssrdf_channel_sample). */
int bssrdf_table_sample(const bssrdf_library *library, size_t table, double rho_prime,
                        double sigma_t_prime, double theta, double u_r, double u_phi,
                        bssrdf_sample *out_sample);

/* The path-tracing draw from four uniforms u[0..3] (bssrdf_channel_sample_path). */
int bssrdf_table_sample_path(const bssrdf_library *library, size_t table, double rho_prime,
                             double sigma_t_prime, const double *u,
                             bssrdf_path_sample *out_sample);

/* Density of theta in bssrdf_table_sample_path, per radian (bssrdf_channel_pdf_theta);
 * sigma_t_prime is checked but does not enter it. */
int bssrdf_table_pdf_theta(const bssrdf_library *library, size_t table, double rho_prime,
                           double sigma_t_prime, double theta, double *out_pdf);

/* Effective albedo rho_eff(theta) (bssrdf_channel_effective_albedo); sigma_t_prime is checked
 * but does not enter it. */
int bssrdf_table_effective_albedo(const bssrdf_library *library, size_t table,
                                  double rho_prime, double sigma_t_prime, double theta,
                                  double *out_albedo);

/* The separable renderers' lookups above, with the medium given per call.
 * The exit distance r in mm from one uniform u in [0, 1), with its density per mm
 * (bssrdf_channel_sample_radius). */
int bssrdf_table_sample_radius(const bssrdf_library *library, size_t table, double rho_prime,
                               double sigma_t_prime, double theta, double u,
                               bssrdf_radial_sample *out_sample);

/* Density per mm of bssrdf_table_sample_radius at r_mm (bssrdf_channel_pdf_radius). */
int bssrdf_table_pdf_radius(const bssrdf_library *library, size_t table, double rho_prime,
                            double sigma_t_prime, double theta, double r_mm, double *out_pdf);

/* The angular factor S / S_bar, dimensionless (bssrdf_channel_angular_factor). */
int bssrdf_table_angular_factor(const bssrdf_library *library, size_t table, double rho_prime,
                                double sigma_t_prime, double theta, double r_mm, double phi,
                                double *out_factor);

/* Batches of n points on table `table`, structures of arrays (see "Batches" above): arrays
 * of n doubles, point i with its own medium (rho_prime[i], sigma_t_prime[i]).
 * S_p in mm^-2 into out_value[i]: bssrdf_table_eval at point i, or 0 where it fails. */
int bssrdf_table_eval_n(const bssrdf_library *library, size_t table, size_t n,
                        const double *rho_prime, const double *sigma_t_prime,
                        const double *theta, const double *r_mm, const double *phi,
                        double *out_value);

/* Density per mm^2 into out_pdf[i]: bssrdf_table_pdf at point i, or 0 where it fails. */
int bssrdf_table_pdf_n(const bssrdf_library *library, size_t table, size_t n,
                       const double *rho_prime, const double *sigma_t_prime,
                       const double *theta, const double *r_mm, const double *phi,
                       double *out_pdf);

/* Draws into out_r[i] (mm), out_phi[i] (radians) and out_pdf[i] (mm^-2):
 * bssrdf_table_sample at point i from the uniforms (u_r[i], u_phi[i]), or the failed draw
 * r = phi = pdf = 0 where it fails (no energy, theta or the medium outside the table). */
int bssrdf_table_sample_n(const bssrdf_library *library, size_t table, size_t n,
                          const double *rho_prime, const double *sigma_t_prime,
                          const double *theta, const double *u_r, const double *u_phi,
                          double *out_r, double *out_phi, double *out_pdf);

/* Draws of the exit distance alone into out_r[i] (mm) and out_pdf[i] (mm^-1):
 * bssrdf_table_sample_radius at point i from the uniform u[i], or the failed draw
 * r = pdf = 0 where it fails. */
int bssrdf_table_sample_radius_n(const bssrdf_library *library, size_t table, size_t n,
                                 const double *rho_prime, const double *sigma_t_prime,
                                 const double *theta, const double *u, double *out_r,
                                 double *out_pdf);

/* Density per mm into out_pdf[i]: bssrdf_table_pdf_radius at point i, or 0 where it fails. */
int bssrdf_table_pdf_radius_n(const bssrdf_library *library, size_t table, size_t n,
                              const double *rho_prime, const double *sigma_t_prime,
                              const double *theta, const double *r_mm, double *out_pdf);

/* The angular factor into out_factor[i]: bssrdf_table_angular_factor at point i, or 0 where
 * it fails. */
int bssrdf_table_angular_factor_n(const bssrdf_library *library, size_t table, size_t n,
                                  const double *rho_prime, const double *sigma_t_prime,
                                  const double *theta, const double *r_mm, const double *phi,
                                  double *out_factor);

/* Path-tracing draws into out_theta[i], out_r[i], out_phi[i], out_phi_prime[i],
 * out_pdf_theta[i] and out_pdf[i] (the fields of bssrdf_path_sample):
 * bssrdf_table_sample_path at point i from the four uniforms u = {u0[i], u1[i], u2[i], u3[i]},
 * or the failed draw, every field 0, where it fails (no energy, the medium outside the table,
 * a table without theta sampling). */
int bssrdf_table_sample_path_n(const bssrdf_library *library, size_t table, size_t n,
                               const double *rho_prime, const double *sigma_t_prime,
                               const double *u0, const double *u1, const double *u2,
                               const double *u3, double *out_theta, double *out_r,
                               double *out_phi, double *out_phi_prime, double *out_pdf_theta,
                               double *out_pdf);

/* The message of the last failed call on this thread (UTF-8, NUL-terminated, "no error" if
 * none yet). Valid until the next failing call on this thread. Never NULL. */
const char *bssrdf_last_error_message(void);

/* The name of a status code's constant ("BSSRDF_ERROR_IO", ...), or "unknown status". Static. */
const char *bssrdf_status_name(int status);

/* Diffuse reflectance: the reduced albedo for an artist's colour.
 *
 * For light arriving at incidence theta (radians, before refraction) the diffuse reflectance of
 * a medium of reduced albedo rho' on a table of relative index eta is
 *   A(rho', theta) = (1 - F_r(cos theta; eta)) rho_eff(rho', theta):
 * the multiply scattered power leaving the surface (anywhere, in any direction) per unit power
 * ARRIVING. rho_eff (bssrdf_channel_effective_albedo) is per unit power entering and already
 * holds the exit Fresnel transmission; 1 - F_r is the unpolarised Fresnel transmittance at
 * entry. What the boundary reflects at once, F_r, is the renderer's specular lobe, not part of
 * A; single scattering is not in the model. Defined in docs/physics.md. */

/* The diffuse reflectance A(rho', theta) of the channel's medium (dimensionless): the inverse
 * of bssrdf_library_invert_albedo, for showing an artist the colour a medium gives.
 * BSSRDF_ERROR_OUT_OF_RANGE for theta outside the table or NaN. Allocates nothing. */
int bssrdf_channel_diffuse_reflectance(const bssrdf_channel *channel, double theta,
                                       double *out_reflectance);

/* bssrdf_channel_diffuse_reflectance with the medium given per call (see "Media per call":
 * the same checks and statuses; sigma_t_prime is checked but does not enter A). */
int bssrdf_table_diffuse_reflectance(const bssrdf_library *library, size_t table,
                                     double rho_prime, double sigma_t_prime, double theta,
                                     double *out_reflectance);

/* The reflectances table `table` reaches at incidence theta: A at its first and at its last
 * albedo row ([0, A(rho' = 1)] for a full table, e.g. [0, 0.931] at theta = 0, eta = 1.33 on the
 * default grid; [0, 0] where no light enters: grazing incidence, beyond the critical angle of
 * an eta below 1). BSSRDF_ERROR_NOT_FOUND for a table index past the end,
 * BSSRDF_ERROR_OUT_OF_RANGE for theta outside the table or NaN. */
int bssrdf_library_reflectance_range(const bssrdf_library *library, size_t table, double theta,
                                     double *out_min, double *out_max);

/* The reduced albedo rho' whose diffuse reflectance A(rho', theta) on table `table` is
 * `reflectance`, in *out_rho_prime: solved on the table's own curve to its resolution (about
 * 1e-7 of A), monotone in the reflectance. No silent clamp: BSSRDF_ERROR_OUT_OF_RANGE for a
 * reflectance outside bssrdf_library_reflectance_range or NaN (the message names the value and
 * the range), for theta outside the table or NaN, and where no light enters at theta;
 * BSSRDF_ERROR_NOT_FOUND for a table index past the end. Allocates nothing on success (a
 * failure formats its message). */
int bssrdf_library_invert_albedo(const bssrdf_library *library, size_t table, double reflectance,
                                 double theta, double *out_rho_prime);

#ifdef __cplusplus
}
#endif

#endif /* BSSRDF_ZOO_H */

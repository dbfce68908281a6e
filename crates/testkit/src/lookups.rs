//! Lookups at arbitrary inputs, shared by the property tests (`crates/zoo/tests/table/arbitrary_inputs.rs`,
//! `crates/capi/tests/capi/arbitrary_inputs.rs`, `crates/zoo/tests/models/arbitrary_inputs.rs`) and the fuzz target
//! `fuzz/fuzz_targets/lookups.rs`, so that both hold the lookups to the same rules:
//! - never a panic, never a NaN or negative value or density (`eval` may be +∞ only where a
//!   model documents it; table lookups are finite);
//! - a draw is either `None` (no sample) or a valid point, inside the support, whose density
//!   is the one `pdf` gives there;
//! - through the C interface, the statuses and values of the Rust handle, bit for bit, with a
//!   channel handle, with the medium given per call and in a batch.
//!
//! Inputs come from (selector, bits) pairs ([`number`]): special values (NaN, ±∞, ±0,
//! subnormals, huge), any f64 bit pattern, the table's own nodes nudged by a few ulps, or a
//! point of the sensible domain, so that every branch of a lookup is met often.

use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::ffi::CString;

use bssrdf::*;
use bssrdf_zoo::embed::{ChannelLookup, Library, TableLookup};
use bssrdf_zoo::format::{Compression, LibraryBuilder};
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::models::Model;
use bssrdf_zoo::table::{
    bake, bake_lobes, rows_for, AngularTable, Grid, Lobes, RhoInterval, TableRef,
};

/// The tables lookups are held to the rules on: `full` (a bake of a whole grid with θ
/// sampling), two scene subsets of its albedo rows (ρ′ ∈ [0.3, 0.6] as a scene bake keeps it,
/// and the first five rows, from ρ′ = 0), `full` without θ sampling, and small bakes at the
/// ends of the η domain (0.75: no light enters beyond 48.6°; 2.5), at η = 1 with pbrt's
/// Fresnel moments, and on a radius axis of three nodes, with one lobe and with two (below
/// η = 1.33 every bake has two, `table::Lobes`).
pub fn tables(full: AngularTable) -> Vec<(&'static str, AngularTable)> {
    let rows = rows_for(full.axes().rho(), RhoInterval::new(0.3, 0.6).unwrap()).unwrap();
    let scene = full.subset_rows(rows).unwrap();
    let low = full.subset_rows(0..5).unwrap();
    let no_theta = full.without_theta_sampling().unwrap();
    let small = Grid::ferrier(8, 4, 12);
    let short = Grid {
        rho: vec![0.2, 0.9],
        theta: vec![0.0, 0.6, FRAC_PI_2],
        r: vec![0.0, 0.01, 0.02],
    };
    let baked = |eta, moments, grid: &Grid| bake(eta, moments, grid, true).unwrap().0;
    vec![
        ("full", full),
        ("scene subset", scene),
        ("low rows", low),
        ("no theta sampling", no_theta),
        ("eta 0.75", baked(0.75, Moments::Exact, &small)),
        ("eta 2.5", baked(2.5, Moments::Exact, &small)),
        ("eta 1 pbrt", baked(1.0, Moments::Pbrt, &small)),
        ("short r axis", baked(1.33, Moments::Exact, &short)),
        (
            "short r axis, two lobes",
            bake_lobes(1.33, Moments::Exact, &short, true, Lobes::Two)
                .unwrap()
                .0,
        ),
    ]
}

/// The tables of [`tables`]`(full)` in one library file (no materials) in a scratch folder,
/// opened mapped by the Rust handles and by the C interface. Neither is ever closed: the
/// fixtures live as long as the process.
pub struct Opened {
    pub rust: Library,
    pub c: *const bssrdf_library,
}

// SAFETY: the C interface allows any number of threads to use a library handle at once, and
// this one is never closed.
unsafe impl Send for Opened {}
// SAFETY: as above.
unsafe impl Sync for Opened {}

/// Writes and opens the file of [`Opened`].
pub fn open_tables(full: AngularTable) -> Opened {
    let mut builder = LibraryBuilder::new();
    for (_, table) in tables(full) {
        builder.add_table(table.to_table_data()).unwrap();
    }
    let path = tempfile::tempdir().unwrap().keep().join("tables.bssrdf");
    std::fs::write(&path, builder.to_bytes(Compression::None).unwrap()).unwrap();
    let rust = Library::open_mmap(&path).unwrap();
    let c_path = CString::new(path.to_str().unwrap()).unwrap();
    let mut c = std::ptr::null_mut();
    // SAFETY: a valid string and output.
    let status = unsafe { bssrdf_library_open(c_path.as_ptr(), BSSRDF_OPEN_MAP, &mut c) };
    assert_eq!(status, BSSRDF_OK);
    Opened { rust, c }
}

/// Values no renderer should send, and some it will.
pub const SPECIAL: [f64; 24] = [
    f64::NAN,
    -f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    0.0,
    -0.0,
    5e-324,
    -5e-324,
    1e-310,
    f64::MIN_POSITIVE,
    1e-300,
    1e-12,
    0.5,
    1.0,
    -1.0,
    1.0 - f64::EPSILON / 2.0,
    1.0 + f64::EPSILON,
    FRAC_PI_2,
    PI,
    -PI,
    TAU,
    1e300,
    f64::MAX,
    f64::MIN,
];

/// One input number from a selector and 64 bits: a special value, any bit pattern, a node of
/// `nodes` moved by −2 … 2 ulps, or a point of [lo, hi].
pub fn number(selector: u8, bits: u64, nodes: &[f64], lo: f64, hi: f64) -> f64 {
    match selector % 8 {
        0 => SPECIAL[(bits % SPECIAL.len() as u64) as usize],
        1 => f64::from_bits(bits),
        2 if !nodes.is_empty() => {
            let x = nodes[(bits % nodes.len() as u64) as usize];
            ulps_away(x, ((bits >> 32) % 5) as i64 - 2)
        }
        _ => lo + (hi - lo) * ((bits >> 11) as f64 / (1u64 << 53) as f64),
    }
}

/// The float `steps` representable numbers above `x` (below for negative `steps`), for
/// finite `x` (`f64::next_up` needs Rust 1.86, above the crate's MSRV).
fn ulps_away(x: f64, steps: i64) -> f64 {
    let mut x = x;
    for _ in 0..steps.unsigned_abs() {
        let up = (steps > 0) == (x >= 0.0);
        x = match (x == 0.0, up) {
            (true, _) => f64::from_bits(1).copysign(steps as f64),
            (false, true) => f64::from_bits(x.to_bits() + 1),
            (false, false) => f64::from_bits(x.to_bits() - 1),
        };
    }
    x
}

/// The arguments of one round of lookups.
#[derive(Debug, Clone, Copy)]
pub struct Inputs {
    /// Reduced albedo ρ′.
    pub rho: f64,
    /// Incidence θ, radians.
    pub theta: f64,
    /// Exit distance, reduced mean free paths (mm through the handles).
    pub r: f64,
    /// Exit azimuth, radians.
    pub phi: f64,
    /// The random numbers of the draws.
    pub u: [f64; 4],
    /// Reduced extinction σ′t, mm⁻¹, for the world-unit handles.
    pub sigma_t: f64,
}

/// Points as a batch takes them, one array per argument: entry i of each from the i-th
/// [`Inputs`] (its ρ′, σ′t, θ, r, φ and its four random numbers: `u_r`, `u_phi`, `u2`, `u3`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Columns {
    pub rho: Vec<f64>,
    pub sigma_t: Vec<f64>,
    pub theta: Vec<f64>,
    pub r: Vec<f64>,
    pub phi: Vec<f64>,
    pub u_r: Vec<f64>,
    pub u_phi: Vec<f64>,
    pub u2: Vec<f64>,
    pub u3: Vec<f64>,
}

impl FromIterator<Inputs> for Columns {
    fn from_iter<I: IntoIterator<Item = Inputs>>(points: I) -> Columns {
        let mut c = Columns::default();
        for x in points {
            let columns = [
                &mut c.rho,
                &mut c.sigma_t,
                &mut c.theta,
                &mut c.r,
                &mut c.phi,
            ];
            for (column, v) in columns
                .into_iter()
                .zip([x.rho, x.sigma_t, x.theta, x.r, x.phi])
            {
                column.push(v);
            }
            c.u_r.push(x.u[0]);
            c.u_phi.push(x.u[1]);
            c.u2.push(x.u[2]);
            c.u3.push(x.u[3]);
        }
        c
    }
}

/// A draw's output that no lookup writes (every field −7), to see that a failed lookup left
/// its output alone.
pub const UNTOUCHED_SAMPLE: bssrdf_sample = bssrdf_sample {
    r: -7.0,
    phi: -7.0,
    pdf: -7.0,
};

/// A path draw's output that no lookup writes (every field −7).
pub const UNTOUCHED_PATH: bssrdf_path_sample = bssrdf_path_sample {
    theta: -7.0,
    r: -7.0,
    phi: -7.0,
    phi_prime: -7.0,
    pdf_theta: -7.0,
    pdf: -7.0,
};

/// Inputs for a table from nine (selector, bits) pairs, each number near the table's own
/// nodes now and then.
pub fn inputs(view: &TableRef, selectors: [u8; 9], bits: [u64; 9]) -> Inputs {
    let axes = view.axes();
    let nodes = [axes.rho(), axes.theta(), axes.r()].map(|n| n.as_slice());
    inputs_near(nodes, selectors, bits)
}

/// Inputs from nine (selector, bits) pairs, near the nodes of ρ′, θ and r now and then, inside
/// their ranges (r up to 1.1 times the last node) otherwise.
pub fn inputs_near(nodes: [&[f64]; 3], selectors: [u8; 9], bits: [u64; 9]) -> Inputs {
    let [rho, theta, r] = nodes;
    let n = |k: usize, nodes: &[f64], lo, hi| number(selectors[k], bits[k], nodes, lo, hi);
    let u = |k: usize| n(k, &[0.0, 1.0], 0.0, 1.0);
    Inputs {
        rho: n(0, rho, rho[0], rho[rho.len() - 1]),
        theta: n(1, theta, theta[0], theta[theta.len() - 1]),
        r: n(2, r, 0.0, 1.1 * r[r.len() - 1]),
        phi: n(3, &[-PI, 0.0, PI], -4.0, 4.0),
        u: [u(4), u(5), u(6), u(7)],
        sigma_t: n(8, &[1.0], 1e-3, 1e3),
    }
}

/// Inputs for a model of the zoo from nine (selector, bits) pairs: near θ = 0, `theta_node`
/// and 90°, r = 0, 1 and 10 now and then, inside θ ∈ [0, π/2] and r ∈ [0, 11] otherwise (ρ′
/// and σ′t are not used).
pub fn model_inputs(theta_node: f64, selectors: [u8; 9], bits: [u64; 9]) -> Inputs {
    let nodes: [&[f64]; 3] = [
        &[0.0, 1.0],
        &[0.0, theta_node, FRAC_PI_2],
        &[0.0, 1.0, 10.0],
    ];
    inputs_near(nodes, selectors, bits)
}

/// Relative difference of two densities, 0 when both are 0.
pub fn rel(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else {
        (a - b).abs() / a.abs().max(b.abs())
    }
}

/// How far a draw's density may be from `pdf` at the drawn point, relatively. The sampler
/// computes the point and its density from one segment parameter; `pdf` finds the parameter
/// again from the point and evaluates the spline by another formula. Both round alike almost
/// everywhere (differences of 1e-13 and less), but where the density nears a zero (the tail of
/// the radial support, θ beyond the critical angle) the spline's value is a small difference
/// of its terms: 1e-8 … 1e-7 appear (7e-8 the largest of 800,000 draws at arbitrary inputs),
/// and more where the density itself is negligible (see [`DENSITY_FLOOR`]).
pub const PDF_TOLERANCE: f64 = 1e-6;

/// Densities, in units of the lookup's unit density (1 per reduced mfp², per radian; σ′t² per
/// mm²), below which a draw's may differ from `pdf`'s by this much absolutely: far in the
/// radial tail (r ≈ 600 mfp, densities of 1e-27) the cancellation leaves 1e-3 of relative
/// difference, and at the end of a tail whose energy underflows f32 (η = 1, pbrt's moments,
/// an 8 × 4 × 12 grid: ρ′ = 0.028, θ = 52.7°, r = 65.5, a draw with u = 1 − 2·10⁻¹⁶) 5·10⁻³ at
/// a density of 6.5·10⁻¹⁷, 10⁻¹⁷ of the slice's at its first radius. Such points hold no
/// probability a renderer would ever draw.
pub const DENSITY_FLOOR: f64 = 1e-16;

/// Whether `drawn`, the density a sampler returned with the point (a, b), is `pdf(a, b)`:
/// within [`PDF_TOLERANCE`] relatively or [`DENSITY_FLOOR`] times `unit` absolutely.
pub fn density_matches(
    drawn: f64,
    pdf: impl Fn(f64, f64) -> f64,
    a: f64,
    b: f64,
    unit: f64,
) -> bool {
    let at = pdf(a, b);
    rel(drawn, at) <= PDF_TOLERANCE || (drawn - at).abs() <= DENSITY_FLOOR * unit
}

fn density(what: &str, value: f64, x: &Inputs) {
    assert!(
        value.is_finite() && value >= 0.0,
        "{what} = {value} at {x:?}"
    );
}

fn azimuth(what: &str, phi: f64, x: &Inputs) {
    assert!((-PI..=PI).contains(&phi), "{what} = {phi} at {x:?}");
}

/// Every reduced-unit lookup of a table at `x`: values and densities finite and ≥ 0, draws
/// inside the support with the density `pdf` gives. Returns how many draws gave a point.
pub fn check_view(view: &TableRef, x: &Inputs) -> usize {
    let Inputs {
        rho,
        theta,
        r,
        phi,
        u,
        ..
    } = *x;
    let axes = view.axes();
    let r_max = *axes.r().as_slice().last().unwrap();
    let thetas = axes.theta().as_slice();
    let (theta_lo, theta_hi) = (thetas[0], thetas[thetas.len() - 1]);
    let mut drawn = 0;
    if let Some(v) = view.eval(rho, theta, r, phi) {
        density("eval", v, x);
    }
    if let Some(v) = view.eval_perpendicular(rho, r) {
        density("eval_perpendicular", v, x);
    }
    if let Some(v) = view.effective_albedo(rho, theta) {
        density("effective_albedo", v, x);
    }
    density("pdf", view.pdf(rho, theta, r, phi), x);
    density("pdf_theta", view.pdf_theta(rho, theta), x);
    if let Some(s) = view.sample(rho, theta, u[0], u[1]) {
        drawn += 1;
        assert!(s.r > 0.0 && s.r <= r_max, "sample r = {} at {x:?}", s.r);
        azimuth("sample phi", s.phi, x);
        assert!(s.pdf > 0.0, "sample pdf {} at {x:?}", s.pdf);
        density("sample pdf", s.pdf, x);
        let pdf = |r, phi| view.pdf(rho, theta, r, phi);
        assert!(
            density_matches(s.pdf, pdf, s.r, s.phi, 1.0),
            "sample {s:?} has pdf {} at {x:?}",
            pdf(s.r, s.phi)
        );
        let value = view.eval(rho, theta, s.r, s.phi);
        assert!(
            value.is_some_and(|v| v.is_finite() && v >= 0.0),
            "{value:?}"
        );
    }
    if let Some(s) = view.sample_perpendicular(rho, u[0], u[1]) {
        drawn += 1;
        assert!(
            s.r > 0.0 && s.r <= r_max,
            "perpendicular r = {} at {x:?}",
            s.r
        );
        azimuth("perpendicular phi", s.phi, x);
        assert!(s.pdf > 0.0, "perpendicular pdf {} at {x:?}", s.pdf);
        density("perpendicular pdf", s.pdf, x);
    }
    if let Some(p) = view.sample_path(rho, u) {
        drawn += 1;
        assert!(
            (theta_lo..=theta_hi).contains(&p.theta),
            "path theta {} at {x:?}",
            p.theta
        );
        assert!(p.r > 0.0 && p.r <= r_max, "path r = {} at {x:?}", p.r);
        azimuth("path phi", p.phi, x);
        azimuth("path phi'", p.phi_prime, x);
        assert!(p.pdf > 0.0 && p.pdf_theta > 0.0, "path {p:?} at {x:?}");
        density("path pdf", p.pdf, x);
        density("path pdf_theta", p.pdf_theta, x);
        let pdf_theta = |theta, _| view.pdf_theta(rho, theta);
        assert!(
            density_matches(p.pdf_theta, pdf_theta, p.theta, 0.0, 1.0),
            "path {p:?}: pdf_theta {} at {x:?}",
            pdf_theta(p.theta, 0.0)
        );
        // The density of (r, φ) given θ: the joint one over θ's (and φ′'s).
        let given = |r, phi| view.pdf(rho, p.theta, r, phi);
        assert!(
            density_matches(p.pdf / p.pdf_theta * TAU, given, p.r, p.phi, 1.0),
            "path {p:?}: pdf given theta {} at {x:?}",
            given(p.r, p.phi)
        );
    }
    if let Some((u_r, u_phi)) = view.invert(rho, theta, r, phi) {
        assert!(
            (0.0..=1.0).contains(&u_r) && (0.0..=1.0).contains(&u_phi),
            "invert gave ({u_r}, {u_phi}) at {x:?}"
        );
    }
    drawn
}

/// The world-unit handle of a medium on `table` at `x` (ρ′ = `x.rho`, σ′t = `x.sigma_t`):
/// refused, or every lookup valid as in [`check_view`]. Returns the handle, if made.
pub fn check_channel(table: &TableLookup, x: &Inputs) -> Option<ChannelLookup> {
    let Inputs {
        theta,
        r,
        phi,
        u,
        sigma_t,
        ..
    } = *x;
    let channel = table.medium(x.rho, sigma_t).ok()?;
    let thetas = table.view().axes().theta().as_slice();
    let (theta_lo, theta_hi) = (thetas[0], thetas[thetas.len() - 1]);
    if let Some(v) = channel.eval(theta, r, phi) {
        density("channel eval", v, x);
    }
    if let Some(v) = channel.effective_albedo(theta) {
        density("channel effective_albedo", v, x);
    }
    density("channel pdf", channel.pdf(theta, r, phi), x);
    density("channel pdf_theta", channel.pdf_theta(theta), x);
    if let Some(s) = channel.sample(theta, u[0], u[1]) {
        assert!(s.r > 0.0 && s.r.is_finite(), "channel r = {} at {x:?}", s.r);
        azimuth("channel phi", s.phi, x);
        assert!(s.pdf > 0.0, "channel pdf {} at {x:?}", s.pdf);
        density("channel sample pdf", s.pdf, x);
        let pdf = |r, phi| channel.pdf(theta, r, phi);
        assert!(
            density_matches(s.pdf, pdf, s.r, s.phi, sigma_t * sigma_t),
            "channel sample {s:?} has pdf {} at {x:?}",
            pdf(s.r, s.phi)
        );
    }
    if let Some(p) = channel.sample_path(u) {
        assert!((theta_lo..=theta_hi).contains(&p.theta), "{p:?} at {x:?}");
        assert!(p.r > 0.0 && p.r.is_finite(), "{p:?} at {x:?}");
        azimuth("channel path phi", p.phi, x);
        azimuth("channel path phi'", p.phi_prime, x);
        assert!(p.pdf > 0.0 && p.pdf_theta > 0.0, "{p:?} at {x:?}");
        density("channel path pdf", p.pdf, x);
        let pdf_theta = |theta, _| channel.pdf_theta(theta);
        assert!(
            density_matches(p.pdf_theta, pdf_theta, p.theta, 0.0, 1.0),
            "{p:?} at {x:?}"
        );
        let given = |r, phi| channel.pdf(p.theta, r, phi);
        assert!(
            density_matches(
                p.pdf / p.pdf_theta * TAU,
                given,
                p.r,
                p.phi,
                sigma_t * sigma_t
            ),
            "channel path {p:?}: pdf given theta {} at {x:?}",
            given(p.r, p.phi)
        );
    }
    Some(channel)
}

/// The C interface on table `table` of `library` at `x`: the status of
/// `bssrdf_library_medium` is the Rust handle's (`rust`: made or refused), and each lookup
/// returns the Rust handle's status and value, bit for bit.
///
/// # Safety
/// `library` is a live handle from `bssrdf_library_open` of the file `rust` was made from.
pub unsafe fn check_capi(
    library: *const bssrdf_library,
    table: usize,
    rust: Option<&ChannelLookup>,
    x: &Inputs,
) {
    let Inputs {
        theta,
        r,
        phi,
        u,
        sigma_t,
        ..
    } = *x;
    let mut channel = std::ptr::null_mut();
    // SAFETY: the caller's handle; a valid output.
    let status = unsafe { bssrdf_library_medium(library, table, x.rho, sigma_t, &mut channel) };
    // SAFETY: the caller's contract.
    unsafe { check_per_call(library, table, rust, status, x) };
    let Some(rust) = rust else {
        assert!(
            status != BSSRDF_OK && channel.is_null(),
            "C made a channel Rust refused at {x:?}"
        );
        return;
    };
    assert_eq!(status, BSSRDF_OK, "C refused a channel Rust made at {x:?}");
    let bits = |v: Option<f64>| v.map(f64::to_bits);
    // C refuses a point outside the domain (OUT_OF_RANGE) where Rust gives 0 or None
    let inside = c_point_inside(&rust.table().view(), theta, r, phi);
    let mut value = f64::NAN;
    // SAFETY: a live channel and valid outputs, here and below.
    let status = unsafe { bssrdf_channel_eval(channel, theta, r, phi, &mut value) };
    let c = (status == BSSRDF_OK).then_some(value);
    let want = rust.eval(theta, r, phi).filter(|_| inside.r_phi);
    assert_eq!(bits(c), bits(want), "eval at {x:?}");
    let status = unsafe { bssrdf_channel_pdf(channel, theta, r, phi, &mut value) };
    let c = (status == BSSRDF_OK).then_some(value);
    let want = (inside.r_phi && inside.theta).then(|| rust.pdf(theta, r, phi));
    assert_eq!(bits(c), bits(want), "pdf at {x:?}");
    let status = unsafe { bssrdf_channel_pdf_theta(channel, theta, &mut value) };
    let c = (status == BSSRDF_OK).then_some(value);
    assert_eq!(
        bits(c),
        bits(inside.theta.then(|| rust.pdf_theta(theta))),
        "{x:?}"
    );
    let status = unsafe { bssrdf_channel_effective_albedo(channel, theta, &mut value) };
    let c = (status == BSSRDF_OK).then_some(value);
    assert_eq!(bits(c), bits(rust.effective_albedo(theta)), "{x:?}");
    let mut sample = bssrdf_sample {
        r: f64::NAN,
        phi: f64::NAN,
        pdf: f64::NAN,
    };
    let status = unsafe { bssrdf_channel_sample(channel, theta, u[0], u[1], &mut sample) };
    let c = (status == BSSRDF_OK).then_some([sample.r, sample.phi, sample.pdf].map(f64::to_bits));
    let expected = rust
        .sample(theta, u[0], u[1])
        .map(|s| [s.r, s.phi, s.pdf].map(f64::to_bits));
    assert_eq!(c, expected, "sample at {x:?}");
    if c.is_none() {
        assert_eq!(status, BSSRDF_ERROR_NO_SAMPLE, "{x:?}");
    }
    let mut path = bssrdf_path_sample {
        theta: f64::NAN,
        r: f64::NAN,
        phi: f64::NAN,
        phi_prime: f64::NAN,
        pdf_theta: f64::NAN,
        pdf: f64::NAN,
    };
    let status = unsafe { bssrdf_channel_sample_path(channel, u.as_ptr(), &mut path) };
    let c = (status == BSSRDF_OK).then_some([
        path.theta,
        path.r,
        path.phi,
        path.phi_prime,
        path.pdf_theta,
        path.pdf,
    ]);
    let expected = rust
        .sample_path(u)
        .map(|p| [p.theta, p.r, p.phi, p.phi_prime, p.pdf_theta, p.pdf]);
    assert_eq!(
        c.map(|v| v.map(f64::to_bits)),
        expected.map(|v| v.map(f64::to_bits)),
        "sample_path at {x:?}"
    );
    // The separable renderers' lookups and the diffuse reflectance
    let mut radial = bssrdf_radial_sample::default();
    let status = unsafe { bssrdf_channel_sample_radius(channel, theta, u[0], &mut radial) };
    let c = (status == BSSRDF_OK).then_some([radial.r, radial.pdf].map(f64::to_bits));
    let expected = rust.sample_radius(theta, u[0]);
    assert_eq!(c, expected.map(|d| [d.r, d.pdf].map(f64::to_bits)), "{x:?}");
    let status = unsafe { bssrdf_channel_pdf_radius(channel, theta, r, &mut value) };
    let c = (status == BSSRDF_OK).then_some(value);
    let want = (inside.r && inside.theta).then(|| rust.pdf_radius(theta, r));
    assert_eq!(bits(c), bits(want), "pdf_radius at {x:?}");
    let status = unsafe { bssrdf_channel_angular_factor(channel, theta, r, phi, &mut value) };
    let c = (status == BSSRDF_OK).then_some(value);
    let want = rust.angular_factor(theta, r, phi).filter(|_| inside.r_phi);
    assert_eq!(bits(c), bits(want), "{x:?}");
    let status = unsafe { bssrdf_channel_diffuse_reflectance(channel, theta, &mut value) };
    let c = (status == BSSRDF_OK).then_some(value);
    assert_eq!(bits(c), bits(rust.diffuse_reflectance(theta)), "{x:?}");
    // SAFETY: made above, released once.
    unsafe { bssrdf_channel_release(channel) };
}

/// Which parts of a point are inside the domain of the C lookups (`capi`'s `distance_or_angle_outside` and `density_at`):
/// θ on the table's axis, r a distance in [0, ∞), and r with φ finite.
pub struct CPointInside {
    pub theta: bool,
    pub r: bool,
    pub r_phi: bool,
}

/// [`CPointInside`] of (θ, r, φ) on `view`.
pub fn c_point_inside(view: &TableRef<'_>, theta: f64, r: f64, phi: f64) -> CPointInside {
    let r_ok = r.is_finite() && r >= 0.0;
    CPointInside {
        theta: view.keeps_theta(theta),
        r: r_ok,
        r_phi: r_ok && phi.is_finite(),
    }
}

/// The C lookups with the medium given per call (`bssrdf_table_*`) and in batches of one
/// point at `x`: per call, the statuses and bits of the Rust handle `rust`, or, where
/// `bssrdf_library_medium` refused the medium with status `refused`, that status and the
/// outputs untouched; in a batch, the handle's value, density and draw, or 0 and the failed
/// draw (0, 0, 0) where the single call fails.
///
/// # Safety
/// As [`check_capi`].
unsafe fn check_per_call(
    library: *const bssrdf_library,
    table: usize,
    rust: Option<&ChannelLookup>,
    refused: std::ffi::c_int,
    x: &Inputs,
) {
    let Inputs {
        rho,
        theta,
        r,
        phi,
        u,
        sigma_t,
    } = *x;
    // The status and bits of a call with one output, -7 untouched
    let one = |call: &dyn Fn(*mut f64) -> std::ffi::c_int| {
        let mut value = -7.0;
        let status = call(&mut value);
        (status, (status == BSSRDF_OK).then_some(value.to_bits()))
    };
    let expect =
        |what: &str, got: (std::ffi::c_int, Option<u64>), want: Option<Option<f64>>| match want {
            None => assert_eq!(got, (refused, None), "{what} of a refused medium at {x:?}"),
            Some(v) => assert_eq!(got.1, v.map(f64::to_bits), "{what} at {x:?}"),
        };
    // C refuses a point outside the domain where Rust gives 0 or None
    let inside = |h: &ChannelLookup| c_point_inside(&h.table().view(), theta, r, phi);
    // SAFETY (every call below): the caller's library handle and valid outputs.
    let got =
        one(&|out| unsafe { bssrdf_table_eval(library, table, rho, sigma_t, theta, r, phi, out) });
    let want = rust.map(|h| h.eval(theta, r, phi).filter(|_| inside(h).r_phi));
    expect("eval", got, want);
    let got =
        one(&|out| unsafe { bssrdf_table_pdf(library, table, rho, sigma_t, theta, r, phi, out) });
    let want = rust.map(|h| {
        let inside = inside(h);
        (inside.r_phi && inside.theta).then(|| h.pdf(theta, r, phi))
    });
    expect("pdf", got, want);
    let got =
        one(&|out| unsafe { bssrdf_table_pdf_theta(library, table, rho, sigma_t, theta, out) });
    let want = rust.map(|h| inside(h).theta.then(|| h.pdf_theta(theta)));
    expect("pdf_theta", got, want);
    let got = one(&|out| unsafe {
        bssrdf_table_effective_albedo(library, table, rho, sigma_t, theta, out)
    });
    expect(
        "effective_albedo",
        got,
        rust.map(|h| h.effective_albedo(theta)),
    );
    let mut s = UNTOUCHED_SAMPLE;
    let status =
        unsafe { bssrdf_table_sample(library, table, rho, sigma_t, theta, u[0], u[1], &mut s) };
    let drawn = rust.map(|h| h.sample(theta, u[0], u[1]));
    match drawn {
        Some(Some(d)) => assert_eq!(
            (status, [s.r, s.phi, s.pdf].map(f64::to_bits)),
            (BSSRDF_OK, [d.r, d.phi, d.pdf].map(f64::to_bits)),
            "sample at {x:?}"
        ),
        _ => {
            let want = if rust.is_some() {
                BSSRDF_ERROR_NO_SAMPLE
            } else {
                refused
            };
            assert_eq!((status, [s.r, s.phi, s.pdf]), (want, [-7.0; 3]), "{x:?}");
        }
    }
    let mut p = UNTOUCHED_PATH;
    let status =
        unsafe { bssrdf_table_sample_path(library, table, rho, sigma_t, u.as_ptr(), &mut p) };
    let got = [p.theta, p.r, p.phi, p.phi_prime, p.pdf_theta, p.pdf];
    match rust.map(|h| h.sample_path(u)) {
        Some(Some(d)) => {
            let want = [d.theta, d.r, d.phi, d.phi_prime, d.pdf_theta, d.pdf];
            assert_eq!(
                (status, got.map(f64::to_bits)),
                (BSSRDF_OK, want.map(f64::to_bits)),
                "sample_path at {x:?}"
            );
        }
        _ => {
            let want = if rust.is_some() {
                BSSRDF_ERROR_NO_SAMPLE
            } else {
                refused
            };
            assert_eq!((status, got), (want, [-7.0; 6]), "{x:?}");
        }
    }
    // A batch of this one point
    let (mut value, mut pdf) = (-7.0, -7.0);
    let (mut out_r, mut out_phi, mut out_pdf) = (-7.0, -7.0, -7.0);
    let status = unsafe {
        bssrdf_table_eval_n(
            library, table, 1, &rho, &sigma_t, &theta, &r, &phi, &mut value,
        )
    };
    assert_eq!(status, BSSRDF_OK);
    let want = rust.and_then(|h| h.eval(theta, r, phi)).unwrap_or(0.0);
    assert_eq!(value.to_bits(), want.to_bits(), "eval_n at {x:?}");
    let status = unsafe {
        bssrdf_table_pdf_n(
            library, table, 1, &rho, &sigma_t, &theta, &r, &phi, &mut pdf,
        )
    };
    assert_eq!(status, BSSRDF_OK);
    let want = rust.map_or(0.0, |h| h.pdf(theta, r, phi));
    assert_eq!(pdf.to_bits(), want.to_bits(), "pdf_n at {x:?}");
    let status = unsafe {
        bssrdf_table_sample_n(
            library,
            table,
            1,
            &rho,
            &sigma_t,
            &theta,
            &u[0],
            &u[1],
            &mut out_r,
            &mut out_phi,
            &mut out_pdf,
        )
    };
    assert_eq!(status, BSSRDF_OK);
    let want = match drawn {
        Some(Some(d)) => [d.r, d.phi, d.pdf],
        _ => [0.0; 3],
    };
    assert_eq!(
        [out_r, out_phi, out_pdf].map(f64::to_bits),
        want.map(f64::to_bits),
        "sample_n at {x:?}"
    );
}

/// A model of the zoo at (θ, r, φ, u) of `x`: `eval` and `pdf` ≥ 0 and not NaN, finite except
/// where the model documents +∞ (`infinite_ok`: a density with an integrable singularity at
/// r = 0 exceeds f64 there), and a draw valid with the density `pdf` gives there.
/// (`effective_albedo` is left out: some models integrate for it, milliseconds a call.)
pub fn check_model(model: &dyn Model, x: &Inputs, infinite_ok: bool) {
    let Inputs {
        theta, r, phi, u, ..
    } = *x;
    let v = model.eval(theta, r, phi);
    assert!(
        v >= 0.0 && (v.is_finite() || infinite_ok),
        "{} eval = {v} at {x:?}",
        model.kind()
    );
    let kind = model.kind();
    let pdf = model.pdf(theta, r, phi);
    assert!(
        pdf >= 0.0 && (pdf.is_finite() || infinite_ok),
        "{kind} pdf = {pdf} at {x:?}"
    );
    if let Some(s) = model.sample(theta, [u[0], u[1]]) {
        // r = 0 is a point of the support where a model's density per area is finite.
        assert!(s.r >= 0.0 && s.r.is_finite(), "{kind} r = {} at {x:?}", s.r);
        azimuth("model phi", s.phi, x);
        assert!(s.pdf > 0.0, "{kind} pdf {} at {x:?}", s.pdf);
        density(&format!("{kind} sample pdf"), s.pdf, x);
        let pdf = |r, phi| model.pdf(theta, r, phi);
        assert!(
            density_matches(s.pdf, pdf, s.r, s.phi, 1.0),
            "{kind} sample {s:?} has pdf {} at {x:?}",
            pdf(s.r, s.phi)
        );
    }
}

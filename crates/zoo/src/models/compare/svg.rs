//! Hand-written SVG plots of a comparison (no plotting dependency): the error/time Pareto
//! picture and, per case, the radial and azimuthal profiles of every model over the walk.

use super::{Case, CompareReport, ProfilePoint};
use crate::models::ModelKind;
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

/// One colour per model, in [`ModelKind::ALL`] order (colour-blind-safe Okabe–Ito palette).
const PALETTE: [&str; 8] = [
    "#E69F00", "#56B4E9", "#009E73", "#0072B2", "#D55E00", "#CC79A7", "#999933", "#000000",
];

fn colour(kind: ModelKind) -> &'static str {
    let i = ModelKind::ALL.iter().position(|&k| k == kind).unwrap_or(0);
    PALETTE[i % PALETTE.len()]
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Writes `pareto.svg` and one `profiles-rho{ρ′}-theta{θ}.svg` per case into `dir` (created if
/// missing); returns the paths written.
pub fn write_svgs(report: &CompareReport, dir: &Path) -> io::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut written = Vec::new();
    let path = dir.join("pareto.svg");
    write(&path, pareto(report))?;
    written.push(path);
    for case in &report.cases {
        let name = format!("profiles-rho{}-theta{}.svg", case.rho, case.theta_deg);
        let path = dir.join(name);
        write(&path, profiles(report, case))?;
        written.push(path);
    }
    Ok(written)
}

/// Writes one figure through the library's safe writer (never tears or replaces a non-file).
fn write(path: &Path, svg: String) -> io::Result<()> {
    crate::format::write_file_atomic(path, svg.as_bytes()).map_err(io::Error::other)
}

/// A plot axis mapping data to pixels.
#[derive(Debug, Clone, Copy)]
struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
    /// Pixel positions of lo and hi.
    a: f64,
    b: f64,
}

impl Axis {
    /// An axis spanning the finite (and, for log, positive) values, padded to decades on log
    /// axes; a default range if there are none.
    fn fit(values: impl Iterator<Item = f64>, log: bool, a: f64, b: f64) -> Self {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in values.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        if lo > hi {
            (lo, hi) = if log { (0.1, 10.0) } else { (0.0, 1.0) };
        }
        if log {
            lo = 10f64.powf(lo.log10().floor());
            hi = 10f64.powf(hi.log10().ceil());
            if hi <= lo {
                hi = lo * 10.0;
            }
        } else if hi <= lo {
            hi = lo + 1.0;
        } else {
            hi += 0.05 * (hi - lo);
        }
        Self { lo, hi, log, a, b }
    }

    fn map(&self, v: f64) -> Option<f64> {
        let t = if self.log {
            if v.is_nan() || v <= 0.0 {
                return None;
            }
            (v.log10() - self.lo.log10()) / (self.hi.log10() - self.lo.log10())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        };
        (t.is_finite() && (-0.05..=1.05).contains(&t)).then_some(self.a + t * (self.b - self.a))
    }

    fn ticks(&self) -> Vec<(f64, String)> {
        if self.log {
            let (e0, e1) = (
                self.lo.log10().round() as i32,
                self.hi.log10().round() as i32,
            );
            let step = ((e1 - e0) / 8).max(1);
            (e0..=e1)
                .step_by(step as usize)
                .map(|e| (10f64.powi(e), format!("1e{e}")))
                .collect()
        } else {
            let span = self.hi - self.lo;
            let raw = span / 6.0;
            let mag = 10f64.powf(raw.log10().floor());
            let step = [1.0, 2.0, 5.0, 10.0]
                .iter()
                .map(|m| m * mag)
                .find(|s| span / s <= 8.0)
                .unwrap_or(10.0 * mag);
            let mut v = (self.lo / step).ceil() * step;
            let mut out = Vec::new();
            while v <= self.hi + 1e-9 * span {
                out.push((v, format!("{}", (v / step).round() * step)));
                v += step;
            }
            out
        }
    }
}

/// Frame, grid, ticks and axis titles of one panel.
fn frame(svg: &mut String, x: &Axis, y: &Axis, x_title: &str, y_title: &str, title: &str) {
    let (left, right, top, bottom) = (x.a, x.b, y.b, y.a);
    let _ = writeln!(
        svg,
        r##"<rect x="{left}" y="{top}" width="{}" height="{}" fill="none" stroke="#333"/>"##,
        right - left,
        bottom - top
    );
    for (v, label) in x.ticks() {
        if let Some(px) = x.map(v) {
            let _ = writeln!(
                svg,
                r##"<line x1="{px:.1}" y1="{top}" x2="{px:.1}" y2="{bottom}" stroke="#ddd"/><text x="{px:.1}" y="{}" font-size="11" text-anchor="middle">{label}</text>"##,
                bottom + 15.0
            );
        }
    }
    for (v, label) in y.ticks() {
        if let Some(py) = y.map(v) {
            let _ = writeln!(
                svg,
                r##"<line x1="{left}" y1="{py:.1}" x2="{right}" y2="{py:.1}" stroke="#ddd"/><text x="{}" y="{:.1}" font-size="11" text-anchor="end">{label}</text>"##,
                left - 4.0,
                py + 4.0
            );
        }
    }
    let _ = writeln!(
        svg,
        r#"<text x="{:.1}" y="{}" font-size="12" text-anchor="middle">{}</text>"#,
        0.5 * (left + right),
        bottom + 32.0,
        escape(x_title)
    );
    let _ = writeln!(
        svg,
        r#"<text x="{}" y="{:.1}" font-size="12" text-anchor="middle" transform="rotate(-90 {} {:.1})">{}</text>"#,
        left - 48.0,
        0.5 * (top + bottom),
        left - 48.0,
        0.5 * (top + bottom),
        escape(y_title)
    );
    let _ = writeln!(
        svg,
        r#"<text x="{:.1}" y="{}" font-size="13" text-anchor="middle">{}</text>"#,
        0.5 * (left + right),
        top - 8.0,
        escape(title)
    );
}

fn header(width: f64, height: f64) -> String {
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="sans-serif">
<rect width="100%" height="100%" fill="white"/>
"#
    )
}

fn legend(svg: &mut String, x: f64, y: f64, entries: &[(String, &str, bool)]) {
    for (k, (label, colour, dashed)) in entries.iter().enumerate() {
        let yy = y + 16.0 * k as f64;
        let dash = if *dashed {
            r#" stroke-dasharray="5 3""#
        } else {
            ""
        };
        let _ = writeln!(
            svg,
            r#"<line x1="{x}" y1="{yy}" x2="{}" y2="{yy}" stroke="{colour}" stroke-width="2"{dash}/><text x="{}" y="{}" font-size="11">{}</text>"#,
            x + 22.0,
            x + 27.0,
            yy + 4.0,
            escape(label)
        );
    }
}

fn pareto(report: &CompareReport) -> String {
    let (w, h) = (760.0, 520.0);
    let usable: Vec<_> = report
        .rows
        .iter()
        .filter_map(|r| Some((r.model, r.ns_per_eval?, r.mean_rel_err?)))
        .filter(|&(_, t, e)| t > 0.0 && e > 0.0)
        .collect();
    let x = Axis::fit(usable.iter().map(|p| p.1), true, 80.0, 560.0);
    let y = Axis::fit(usable.iter().map(|p| p.2), true, 460.0, 40.0);
    let mut svg = header(w, h);
    frame(
        &mut svg,
        &x,
        &y,
        "evaluation time (ns, log)",
        "mean relative error over well-resolved bins (log)",
        &format!(
            "Error against time, η = {}, g = {}, {} photons",
            report.eta, report.g, report.photons
        ),
    );
    let mut entries = Vec::new();
    for kind in ModelKind::ALL {
        let points: Vec<_> = usable.iter().filter(|p| p.0 == kind).collect();
        if points.is_empty() {
            continue;
        }
        let c = colour(kind);
        for p in &points {
            if let (Some(px), Some(py)) = (x.map(p.1), y.map(p.2)) {
                let _ = writeln!(
                    svg,
                    r#"<circle cx="{px:.1}" cy="{py:.1}" r="3" fill="{c}" fill-opacity="0.45"/>"#
                );
            }
        }
        // Per model: geometric mean time, arithmetic mean error over the cases.
        let n = points.len() as f64;
        let t = (points.iter().map(|p| p.1.ln()).sum::<f64>() / n).exp();
        let e = points.iter().map(|p| p.2).sum::<f64>() / n;
        if let (Some(px), Some(py)) = (x.map(t), y.map(e)) {
            let _ = writeln!(
                svg,
                r##"<circle cx="{px:.1}" cy="{py:.1}" r="7" fill="{c}" stroke="#000"/><text x="{:.1}" y="{:.1}" font-size="11">{kind}</text>"##,
                px + 9.0,
                py - 6.0
            );
        }
        entries.push((kind.to_string(), c, false));
    }
    legend(&mut svg, 580.0, 60.0, &entries);
    let _ = writeln!(
        svg,
        r#"<text x="580" y="{:.0}" font-size="11">small dots: one per case</text><text x="580" y="{:.0}" font-size="11">large: mean error, geometric</text><text x="580" y="{:.0}" font-size="11">mean time over the cases</text>"#,
        80.0 + 16.0 * entries.len() as f64,
        96.0 + 16.0 * entries.len() as f64,
        112.0 + 16.0 * entries.len() as f64,
    );
    svg.push_str("</svg>\n");
    svg
}

/// A model series and the walk with error bars, in one panel.
fn series(
    svg: &mut String,
    x: &Axis,
    y: &Axis,
    points: &[ProfilePoint],
    centre: impl Fn(&ProfilePoint) -> f64,
    models: &[ModelKind],
) {
    for (m, &kind) in models.iter().enumerate() {
        let mut path = String::new();
        for p in points {
            match (x.map(centre(p)), y.map(p.models[m])) {
                (Some(px), Some(py)) => {
                    let _ = write!(
                        path,
                        "{}{px:.1},{py:.1} ",
                        if path.is_empty() { "M" } else { "L" }
                    );
                }
                _ => {
                    if !path.is_empty() {
                        let _ = writeln!(
                            svg,
                            r#"<path d="{path}" fill="none" stroke="{}" stroke-width="1.6"/>"#,
                            colour(kind)
                        );
                        path.clear();
                    }
                }
            }
        }
        if !path.is_empty() {
            let _ = writeln!(
                svg,
                r#"<path d="{path}" fill="none" stroke="{}" stroke-width="1.6"/>"#,
                colour(kind)
            );
        }
    }
    // The walk: total (filled) and multiple scattering (open), ±1 standard error.
    for (value, err, fill) in [
        (
            (|p: &ProfilePoint| p.walk_total) as fn(&ProfilePoint) -> f64,
            (|p: &ProfilePoint| p.walk_total_stderr) as fn(&ProfilePoint) -> f64,
            "#444",
        ),
        (
            |p: &ProfilePoint| p.walk_multiple,
            |p: &ProfilePoint| p.walk_multiple_stderr,
            "white",
        ),
    ] {
        for p in points {
            let (v, e) = (value(p), err(p));
            let Some(px) = x.map(centre(p)) else { continue };
            let Some(py) = y.map(v) else { continue };
            let top = y.map(v + e).unwrap_or(py);
            let bottom = y.map((v - e).max(v * 1e-3)).unwrap_or(py);
            let _ = writeln!(
                svg,
                r##"<line x1="{px:.1}" y1="{top:.1}" x2="{px:.1}" y2="{bottom:.1}" stroke="#444"/><circle cx="{px:.1}" cy="{py:.1}" r="2.5" fill="{fill}" stroke="#444"/>"##
            );
        }
    }
}

fn profiles(report: &CompareReport, case: &Case) -> String {
    let (w, h) = (1180.0, 500.0);
    let mut svg = header(w, h);
    let radial_centre = |p: &ProfilePoint| (p.lo * p.hi).sqrt();
    let values = |pts: &[ProfilePoint]| -> Vec<f64> {
        pts.iter()
            .flat_map(|p| {
                let mut v = vec![p.walk_total, p.walk_multiple];
                v.extend(&p.models);
                v
            })
            .collect()
    };
    let x = Axis::fit(case.radial.iter().map(radial_centre), true, 80.0, 520.0);
    let mut y = Axis::fit(values(&case.radial).into_iter(), true, 440.0, 50.0);
    // Keep ten decades below the peak: the far tails only compress the picture.
    y.lo = y.lo.max(y.hi * 1e-10);
    frame(
        &mut svg,
        &x,
        &y,
        "r (reduced mean free paths)",
        "azimuthal mean of R (per mfp², per unit power entering)",
        &format!(
            "ρ′ = {}, θ = {}°, η = {}: radial",
            case.rho, case.theta_deg, report.eta
        ),
    );
    series(&mut svg, &x, &y, &case.radial, radial_centre, &case.models);

    let phi_centre = |p: &ProfilePoint| 0.5 * (p.lo + p.hi);
    let x2 = Axis {
        lo: -180.0,
        hi: 180.0,
        log: false,
        a: 640.0,
        b: 960.0,
    };
    let y2 = Axis::fit(values(&case.azimuthal).into_iter(), false, 440.0, 50.0);
    let y2 = Axis { lo: 0.0, ..y2 };
    frame(
        &mut svg,
        &x2,
        &y2,
        "φ (degrees, 0 forward)",
        "",
        &format!(
            "azimuthal, r ∈ [{:.3}, {:.3}] mfp",
            case.azimuthal_shell.0, case.azimuthal_shell.1
        ),
    );
    series(
        &mut svg,
        &x2,
        &y2,
        &case.azimuthal,
        phi_centre,
        &case.models,
    );

    let mut entries: Vec<(String, &str, bool)> = case
        .models
        .iter()
        .map(|&k| (k.to_string(), colour(k), false))
        .collect();
    entries.push(("walk total (filled), ±1σ".to_owned(), "#444", false));
    entries.push(("walk multiple (open), ±1σ".to_owned(), "#444", true));
    legend(&mut svg, 985.0, 60.0, &entries);
    let (s, m, t) = (
        case.walk_reflectance[0],
        case.walk_reflectance[1],
        case.walk_reflectance[2],
    );
    let _ = writeln!(
        svg,
        r#"<text x="985" y="260" font-size="11">walk reflectance</text><text x="985" y="276" font-size="11">single {:.4} ± {:.4}</text><text x="985" y="292" font-size="11">multiple {:.4} ± {:.4}</text><text x="985" y="308" font-size="11">total {:.4} ± {:.4}</text><text x="985" y="324" font-size="11">albedo a = {:.5}</text>"#,
        s.0, s.1, m.0, m.1, t.0, t.1, case.albedo
    );
    svg.push_str("</svg>\n");
    svg
}

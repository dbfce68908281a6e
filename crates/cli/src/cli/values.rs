//! Numbers on the command line: how messages print them, the one range check, the one parser of
//! comma-separated lists, and the one refusal of a ρ′ outside a table's kept albedo rows.

use super::CliError;
use bssrdf_zoo::table::TableRef;
use std::ops::{Bound, RangeBounds};
use std::str::FromStr;

/// A number in a message: the library's one formatter ([`bssrdf_zoo::error::number`]), the
/// shortest of plain and exponent form (1e308, not 309 digits; 1e-9, not 0.000000001).
pub fn show(v: f64) -> String {
    bssrdf_zoo::error::number(v)
}

/// A whole number (a count, a range's end) as messages print it: through [`show`], so
/// `1e12` and `131072` as the help writes them, or in digits where its f64 is not exact.
pub fn show_whole(n: u64) -> String {
    let x = n as f64;
    if x < 9007199254740992.0 || x as u64 == n {
        show(x)
    } else {
        n.to_string()
    }
}

/// An albedo band's edge as messages and tables print it: to 4 decimals (a scene bake's bands
/// end at its kept rows, f32 values such as 0.47971081733703613; `--json` keeps them whole).
pub fn show_band(v: f64) -> String {
    show_rounded(v, 4)
}

/// An angle band's edge in degrees as messages and tables print it: to 3 decimals (the check's
/// band below the critical angle ends at asin η less 10⁻⁶ of it, 64.15800307876565° at η = 0.9).
pub fn show_deg(v: f64) -> String {
    show_rounded(v, 3)
}

/// `v` rounded to `places` decimals, then as [`show`] prints it.
fn show_rounded(v: f64, places: i32) -> String {
    let scale = 10f64.powi(places);
    show((v * scale).round() / scale)
}

/// Whether light enters at incidence `theta_deg` (degrees) below η = 1: sin θ ≤ η, the walk's
/// own check. Always for η ≥ 1.
pub fn enters(theta_deg: f64, eta: f64) -> bool {
    eta >= 1.0 || theta_deg.to_radians().sin() <= eta
}

/// The largest incidence in degrees that [`enters`] takes below η = 1, the critical angle
/// asin η as the check sees it: the messages state it, so that the printed bound is itself
/// accepted (asin η in degrees can round just above it: at η = 0.8 its sine is 0.8 + 2e-16).
pub fn critical_deg(eta: f64) -> f64 {
    last_degree(eta, |theta| enters(theta, eta))
}

/// The largest incidence in degrees, near the critical angle asin η of an η < 1, that `takes`
/// (a command's own test of whether light enters) accepts: what its message prints, so that
/// the printed bound is itself accepted.
pub fn last_degree(eta: f64, takes: impl Fn(f64) -> bool) -> f64 {
    let mut theta = eta.min(1.0).asin().to_degrees();
    while !takes(theta) && theta > 0.0 {
        theta = neighbour(theta, -1);
    }
    while takes(neighbour(theta, 1)) && neighbour(theta, 1) <= 90.0 {
        theta = neighbour(theta, 1);
    }
    theta
}

/// The next f64 above (`step` 1) or below (−1) a positive finite `x` (`f64::next_up` and
/// `next_down` are newer than the crate's minimum Rust).
fn neighbour(x: f64, step: i64) -> f64 {
    f64::from_bits(x.to_bits().wrapping_add_signed(step))
}

/// An azimuth in degrees as radians, reduced to [−180°, 180°] first: whole turns are exact in
/// degrees but not after multiplying by π/180 (360° would become sin φ = −2.4e-16, not 0).
pub fn azimuth_radians(phi_deg: f64) -> f64 {
    // fmod is exact, and so is the shift by 360 of a value in (180, 360) (Sterbenz).
    let mut reduced = phi_deg % 360.0;
    if reduced > 180.0 {
        reduced -= 360.0;
    } else if reduced < -180.0 {
        reduced += 360.0;
    }
    reduced.to_radians()
}

/// Refuses `value` outside `range` (and NaN and ±∞ always); `name` is how the input calls it
/// (`--rho`, `column rho`): "--theta 95 is outside the valid range: [0, 90]".
pub fn check_range(name: &str, value: f64, range: impl RangeBounds<f64>) -> Result<(), CliError> {
    if value.is_finite() && range.contains(&value) {
        return Ok(());
    }
    let domain = match (range.start_bound(), range.end_bound()) {
        (Bound::Unbounded, Bound::Unbounded) => "any finite number".to_string(),
        (Bound::Included(a), Bound::Unbounded) => format!("a finite number >= {}", show(*a)),
        (Bound::Excluded(a), Bound::Unbounded) => format!("a finite number > {}", show(*a)),
        (start, end) => {
            let (open, a) = match start {
                Bound::Included(a) => ("[", show(*a)),
                Bound::Excluded(a) => ("(", show(*a)),
                Bound::Unbounded => ("(", "-inf".to_string()),
            };
            let (b, close) = match end {
                Bound::Included(b) => (show(*b), "]"),
                Bound::Excluded(b) => (show(*b), ")"),
                Bound::Unbounded => ("inf".to_string(), ")"),
            };
            format!("{open}{a}, {b}{close}")
        }
    };
    // A number beyond f64's range parses to ±inf: say so, or `1e400` would come back as `inf`
    let overflow = if value.is_infinite() {
        " (a number beyond ±1.8e308 reads as ±inf)"
    } else {
        ""
    };
    Err(CliError::input(format!(
        "{name} {} is outside the valid range: {domain}{overflow}",
        show(value)
    )))
}

/// A whole number as an option takes it (counts, seeds, indices, levels), also in exponent
/// form (`--photons 1e6`), or what is wrong with the text: clap's own parse says "invalid digit
/// found in string" for `-1` or `1.5`. The commands check their own ranges after it.
pub fn whole<T: FromStr + Whole>(text: &str) -> Result<T, String> {
    let text = text.trim();
    if let Ok(value) = text.parse::<T>() {
        return Ok(value);
    }
    let Ok(x) = text.parse::<f64>() else {
        return Err(format!("{text:?} is not a whole number"));
    };
    // A number typed with digits but beyond ±1.8e308 reads as ±inf: too large or too small
    // below, as typed; NaN and a spelled-out infinity are not numbers of any range
    let not_whole = if x.is_infinite() {
        !text.bytes().any(|b| b.is_ascii_digit())
    } else {
        x.is_nan() || x.fract() != 0.0
    };
    if not_whole {
        return Err(format!("{} is not a whole number", show(x)));
    }
    // Integral: in decimal digits (exact for every integral f64 below 2^127), for T's own parse
    let digits = (x.abs() < 1.7e38).then(|| format!("{}", x as i128));
    // Out of T's range: the number as typed (its f64 may have rounded) and the range
    let range = format!("[{}, {}]", T::MIN_TEXT, T::MAX_TEXT);
    match digits.and_then(|d| d.parse::<T>().ok()) {
        Some(value) => Ok(value),
        None if x < 0.0 && T::MIN_TEXT == "0" => Err(format!(
            "{text} is negative: a whole number in {range} is expected"
        )),
        None if x < 0.0 => Err(format!(
            "{text} is too small: a whole number in {range} is expected"
        )),
        None => Err(format!(
            "{text} is too large: a whole number in {range} is expected"
        )),
    }
}

/// The range of a whole-number type, for [`whole`]'s messages.
pub trait Whole {
    const MIN_TEXT: &'static str;
    const MAX_TEXT: &'static str;
}

impl Whole for u64 {
    const MIN_TEXT: &'static str = "0";
    const MAX_TEXT: &'static str = "18446744073709551615";
}

impl Whole for usize {
    const MIN_TEXT: &'static str = "0";
    #[cfg(target_pointer_width = "64")]
    const MAX_TEXT: &'static str = "18446744073709551615";
    #[cfg(not(target_pointer_width = "64"))]
    const MAX_TEXT: &'static str = "4294967295";
}

impl Whole for i32 {
    const MIN_TEXT: &'static str = "-2147483648";
    const MAX_TEXT: &'static str = "2147483647";
}

/// Every item of a comma-separated list, parsed as `T` ("x" is not a number).
pub fn list<T: FromStr>(text: &str) -> Result<Vec<T>, String> {
    text.split(',')
        .map(|t| {
            t.trim()
                .parse::<T>()
                .map_err(|_| format!("{:?} is not a number", t.trim()))
        })
        .collect()
}

/// Exactly `N` comma-separated values, `shape` naming them ("R,G,B"); clap reports the error
/// with exit code 2.
pub fn exactly<T: FromStr, const N: usize>(text: &str, shape: &str) -> Result<[T; N], String> {
    let values = list::<T>(text)?;
    let count = values.len();
    <[T; N]>::try_from(values)
        .map_err(|_| format!("expected {N} comma-separated numbers {shape}, got {count}"))
}

/// Refuses an incidence outside the θ axis `table` keeps (a subset of the angles may start
/// above 0 or end below 90°): the table is never extrapolated. `theta_deg` as given, in
/// degrees; compared in radians as the lookups take it (`TableRef::keeps_theta`: an end node
/// given in degrees counts as the node).
pub fn check_theta_kept(name: &str, theta_deg: f64, table: &TableRef<'_>) -> Result<(), CliError> {
    if table.keeps_theta(theta_deg.to_radians()) {
        return Ok(());
    }
    let nodes = table.axes().theta().as_slice();
    let (Some(&lo), Some(&hi)) = (nodes.first(), nodes.last()) else {
        return Err(CliError::input("the table has no incidence angles"));
    };
    Err(CliError::input(format!(
        "{name} {} is outside the incidence range this table keeps, [{}, {}] deg: the table is never extrapolated",
        show(theta_deg),
        show_deg(lo.to_degrees()),
        show_deg(hi.to_degrees())
    )))
}

/// Refuses a ρ′ outside the albedo rows table `index` of a file keeps: the table is never
/// extrapolated. `name` says where ρ′ came from (`--rho`, `column rho`, `--material skin1`);
/// `siblings` are the file's other tables of the same η with the rows each keeps, of which
/// the message names one that keeps ρ′ (a scene bake keeps several tables per η).
pub fn check_kept(
    name: &str,
    rho: f64,
    (index, table): (usize, &TableRef<'_>),
    siblings: &[(usize, [f64; 2])],
) -> Result<(), CliError> {
    if table.keeps_rho(rho) {
        return Ok(());
    }
    let (lo, hi) = (table.axes().rho().first(), table.axes().rho().last());
    let elsewhere = match siblings.iter().find(|(_, [a, b])| (*a..=*b).contains(&rho)) {
        Some((other, _)) => {
            format!("; table {other}, of the same eta, keeps it: give --table {other}")
        }
        None => String::new(),
    };
    Err(CliError::input(format!(
        "{name} {} is outside the albedo range table {index} keeps, [{}, {}]: the table is never extrapolated{elsewhere}",
        show(rho),
        show(lo),
        show(hi)
    )))
}

#[cfg(test)]
mod tests {
    use super::{critical_deg, enters, neighbour, show_band, whole};

    #[test]
    fn whole_numbers_say_what_is_wrong() {
        assert_eq!(whole::<u64>("1e6"), Ok(1_000_000));
        assert_eq!(whole::<u64>(" 42 "), Ok(42));
        assert_eq!(whole::<i32>("-3"), Ok(-3));
        assert_eq!(
            whole::<u64>("-1").unwrap_err(),
            "-1 is negative: a whole number in [0, 18446744073709551615] is expected"
        );
        assert_eq!(
            whole::<u64>("1.5").unwrap_err(),
            "1.5 is not a whole number"
        );
        let i32_range = "a whole number in [-2147483648, 2147483647] is expected";
        assert_eq!(
            whole::<i32>("1e10").unwrap_err(),
            format!("1e10 is too large: {i32_range}")
        );
        assert_eq!(
            whole::<i32>("-1e10").unwrap_err(),
            format!("-1e10 is too small: {i32_range}")
        );
        assert_eq!(
            whole::<u64>("1e300").unwrap_err(),
            "1e300 is too large: a whole number in [0, 18446744073709551615] is expected"
        );
        // Exponent forms up to the type's range, and as typed beyond it
        assert_eq!(whole::<u64>("1e16"), Ok(10_000_000_000_000_000));
        assert_eq!(whole::<u64>("1.5e19"), Ok(15_000_000_000_000_000_000));
        assert!(whole::<u64>("18446744073709551616")
            .unwrap_err()
            .starts_with("18446744073709551616 is too large"));
        assert_eq!(
            whole::<usize>("x").unwrap_err(),
            "\"x\" is not a whole number"
        );
        assert_eq!(
            whole::<u64>("nan").unwrap_err(),
            "NaN is not a whole number"
        );
        // Beyond f64 (it reads as ±inf): as typed, too large or too small
        assert_eq!(
            whole::<u64>("1e400").unwrap_err(),
            "1e400 is too large: a whole number in [0, 18446744073709551615] is expected"
        );
        assert_eq!(
            whole::<i32>("-1e400").unwrap_err(),
            format!("-1e400 is too small: {i32_range}")
        );
        assert_eq!(
            whole::<u64>("inf").unwrap_err(),
            "inf is not a whole number"
        );
    }

    #[test]
    fn band_edges_print_to_four_decimals() {
        assert_eq!(show_band(0.47971081733703613), "0.4797");
        assert_eq!(show_band(0.15068472921848297), "0.1507");
        assert_eq!(show_band(1.0), "1");
        assert_eq!(show_band(0.95), "0.95");
    }

    /// The critical angle the messages state is the largest incidence the check takes, at every
    /// η below 1 (asin η in degrees alone is refused at about 8 % of them, η = 0.8 among them).
    #[test]
    fn the_stated_critical_angle_is_the_last_one_taken() {
        for k in 0..2500 {
            let eta = 0.75 + 0.25 * k as f64 / 2500.0;
            let theta = critical_deg(eta);
            assert!(enters(theta, eta), "{eta}: {theta}");
            assert!(!enters(neighbour(theta, 1), eta), "{eta}: {theta}");
        }
        assert!(!enters(0.8f64.asin().to_degrees(), 0.8));
    }
}

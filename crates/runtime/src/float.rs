//! Stepping between adjacent floats, for strict bounds taken as closed ones and for tests at
//! the neighbours of a value (`f64::next_up` and `f64::next_down` need Rust 1.86; the crate's
//! MSRV is 1.85).

/// The float next to `x` in the direction of `towards` (`x` itself if they are equal or `x`
/// is not finite; ±∞ past the largest finite float).
pub fn next_towards(x: f64, towards: f64) -> f64 {
    if x == towards || !x.is_finite() {
        return x;
    }
    if x == 0.0 {
        return f64::from_bits(1).copysign(towards);
    }
    // Away from zero increments the bit pattern, towards zero decrements it
    let bits = x.to_bits();
    let away = (towards > x) == (x > 0.0);
    f64::from_bits(if away { bits + 1 } else { bits - 1 })
}

/// The float after the finite `x` (+∞ after the largest).
pub fn next_up(x: f64) -> f64 {
    next_towards(x, f64::INFINITY)
}

/// The float before the finite `x` (−∞ before the lowest).
pub fn next_down(x: f64) -> f64 {
    next_towards(x, f64::NEG_INFINITY)
}

/// Half an f32 step, relative: how far an f64 value can lie from the f32 it rounds to.
const F32_HALF_STEP: f64 = 1.0 / (1u32 << 24) as f64;

/// [first, last] widened at each end by f32 rounding (2⁻²⁴ of the end): the values an axis of
/// f32 nodes takes, since a value given in f64 (45° in radians, ρ′ = 0.9, or a node printed in
/// its shortest f32 form) lies up to that far from the f32 node it names.
pub fn f32_rounding_around(first: f64, last: f64) -> [f64; 2] {
    [
        first - first.abs() * F32_HALF_STEP,
        last + last.abs() * F32_HALF_STEP,
    ]
}

/// `x`, or `first` or `last` where `x` lies outside [first, last] but inside `domain`.
pub fn snap_to_ends(x: f64, [first, last]: [f64; 2], [lo, hi]: [f64; 2]) -> f64 {
    if x < first && x >= lo {
        first
    } else if x > last && x <= hi {
        last
    } else {
        x
    }
}

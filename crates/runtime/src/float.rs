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

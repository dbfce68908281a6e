//! Typed errors of the library: one variant per failure, messages in lowercase that name the
//! offending value and what would be valid. The binary adds context and maps them to exit codes.

use thiserror::Error;

/// Every error the library returns.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Error {
    /// A physical parameter is NaN or infinite.
    #[error("{name} = {value} is not a finite number")]
    NotFinite { name: &'static str, value: f64 },
    /// A coefficient that must be non-negative is negative.
    #[error("{name} = {value} is negative; it must be >= 0")]
    Negative { name: &'static str, value: f64 },
    /// The Henyey–Greenstein asymmetry is outside the open interval (-1, 1).
    #[error("g = {0} is outside (-1, 1)")]
    AsymmetryOutOfRange(f64),
    /// σ′t = σ′s + σa is zero: the medium neither scatters nor absorbs.
    #[error("reduced extinction sigma_t' = 0 (sigma_s*(1-g) + sigma_a): the medium is vacuum")]
    Vacuum,
    /// A table's arrays are inconsistent with its axes or hold non-finite values.
    #[error(transparent)]
    Table(#[from] TableError),
    /// A value is outside the range the quantity allows.
    #[error("{name} = {} is outside [{}, {}]", Number(*value), Number(*min), Number(*max))]
    OutOfRange {
        name: &'static str,
        value: f64,
        min: f64,
        max: f64,
    },
    /// A quantity that must be strictly positive is zero or negative.
    #[error("{name} = {value} must be > 0")]
    NotPositive { name: &'static str, value: f64 },
    /// Two edges of a range are not in increasing order.
    #[error("{lo_name} = {lo} must be below {hi_name} = {hi}")]
    EdgesNotIncreasing {
        lo_name: &'static str,
        lo: f64,
        hi_name: &'static str,
        hi: f64,
    },
    /// A count (photons, bins) is outside the range the code accepts.
    #[error("{name} = {value} is outside [{min}, {max}]")]
    CountOutOfRange {
        name: &'static str,
        value: u64,
        min: u64,
        max: u64,
    },
    /// A reduced albedo ρ′ lies outside the albedo rows a table keeps (or is NaN): a table is
    /// never extrapolated (a scene bake keeps only some rows).
    #[error("reduced albedo rho' = {} is outside [{}, {}], the table's albedo rows (never extrapolated)", Number(*rho), Number(*min), Number(*max))]
    AlbedoOutsideTable { rho: f64, min: f64, max: f64 },
    /// An array of a batch of lookups has another length than the batch's output.
    #[error("{name} holds {len} values; the batch has {expected} points (the output's length)")]
    BatchLength {
        name: &'static str,
        len: usize,
        expected: usize,
    },
    /// Two values that must agree do not (e.g. a shared table baked for another η).
    #[error("{name} = {found} does not match the required {expected}")]
    Mismatch {
        name: &'static str,
        found: String,
        expected: String,
    },
}

/// Why a table's arrays were rejected.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum TableError {
    /// An array does not have the length the axes imply.
    #[error("{name} has {len} values; the axes ({nrho}x{ntheta}x{nr}) need {expected}")]
    Length {
        name: &'static str,
        len: usize,
        expected: usize,
        nrho: usize,
        ntheta: usize,
        nr: usize,
    },
    /// The axes stored in a file are not valid spline nodes.
    #[error("a table axis is not strictly increasing and finite")]
    Axes,
    /// An axis of a file's table has fewer than two nodes: a valid file (format-spec.md allows
    /// any subset of the axes, including one node), but the lookups interpolate along every
    /// axis.
    #[error(
        "axis {axis} has {len} node(s): lookups interpolate along every axis and need at least 2 (the file itself is valid)"
    )]
    AxisTooShort { axis: &'static str, len: usize },
    /// The relative index of refraction is outside the models' domain.
    #[error("eta = {} is outside [{}, {}]", Number(*value), Number(*min), Number(*max))]
    Eta { value: f64, min: f64, max: f64 },
    /// A value is NaN or infinite.
    #[error("{name}[{index}] = {value} is not finite")]
    NotFinite {
        name: &'static str,
        index: usize,
        value: f32,
    },
}

/// A number as a message shows it: plain where that is short (0.75, 2.5, 300), in exponent form
/// where it is not (1e-9, 1e308 rather than 309 digits).
pub fn number(x: f64) -> String {
    Number(x).to_string()
}

/// [`number`] as a `Display` that allocates nothing, so that the messages of the errors above
/// can be written into a fixed buffer (the C interface does, on its lookup paths). Of an f32
/// (`Number(x_f32)`), its own shortest form: a stored value as the file holds it.
#[derive(Debug, Clone, Copy)]
pub struct Number<T = f64>(pub T);

impl<T: std::fmt::Display + std::fmt::LowerExp> std::fmt::Display for Number<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let x = &self.0;
        if length(format_args!("{x}")) <= length(format_args!("{x:e}")) {
            write!(f, "{x}")
        } else {
            write!(f, "{x:e}")
        }
    }
}

/// The length in bytes of formatted text, counted without storing it.
fn length(text: std::fmt::Arguments<'_>) -> usize {
    struct Count(usize);
    impl std::fmt::Write for Count {
        fn write_str(&mut self, s: &str) -> std::fmt::Result {
            self.0 += s.len();
            Ok(())
        }
    }
    let mut count = Count(0);
    // Counting never fails.
    let _ = std::fmt::Write::write_fmt(&mut count, text);
    count.0
}

/// Result with the library's error type.
pub type Result<T> = std::result::Result<T, Error>;

/// Checks that `value` is finite, naming it in the error otherwise.
pub fn finite(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::NotFinite { name, value })
    }
}

/// Checks that `value` is finite and within `[min, max]`.
pub fn in_range(name: &'static str, value: f64, min: f64, max: f64) -> Result<f64> {
    finite(name, value)?;
    if (min..=max).contains(&value) {
        Ok(value)
    } else {
        Err(Error::OutOfRange {
            name,
            value,
            min,
            max,
        })
    }
}

/// Checks that `value` is finite and ≥ 0 (−0 allowed), naming it in the error otherwise.
pub fn non_negative(name: &'static str, value: f64) -> Result<f64> {
    finite(name, value)?;
    if value < 0.0 {
        return Err(Error::Negative { name, value });
    }
    Ok(value)
}

//! Errors of the renderer, its files and its differences: one variant per failure, each naming
//! the value or file at fault.

use std::path::PathBuf;

/// Every error of [`crate::render`].
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A physical or numerical parameter was rejected (the library's own error names it).
    #[error(transparent)]
    Parameter(#[from] crate::Error),
    /// The model is one a render cannot draw (it draws [`super::MODELS`]).
    #[error("render cannot draw the {name} model; it draws {expected}")]
    Model {
        name: &'static str,
        expected: String,
    },
    /// The walk-table model has no walk table for the material.
    #[error("the walk-table model cannot draw: {why}")]
    WalkTable { why: String },
    /// The image size is outside 1 ..= [`super::MAX_SIDE`] pixels per side.
    #[error("image size {width}x{height} is outside 1..={max} pixels per side")]
    Size {
        width: usize,
        height: usize,
        max: usize,
    },
    /// θ plus the cone's half-angle reaches grazing incidence, where no light enters.
    #[error(
        "theta = {theta_deg} deg plus cone = {cone_deg} deg must stay below 90 deg (grazing light does not enter)"
    )]
    Grazing { theta_deg: f64, cone_deg: f64 },
    /// Writing or encoding an EXR file failed.
    #[error("cannot write {}: {message}", path.display())]
    WriteExr { path: PathBuf, message: String },
    /// Reading or decoding an EXR file failed.
    #[error("cannot read {}: {message}", path.display())]
    ReadExr { path: PathBuf, message: String },
    /// An EXR file lacks a channel or attribute a render writes.
    #[error("{} is not a bssrdf render: no {what}", path.display())]
    NotARender { path: PathBuf, what: String },
    /// Writing the PNG preview failed.
    #[error("cannot write {}: {message}", path.display())]
    WritePng { path: PathBuf, message: String },
    /// Two renders to compare differ in a property that must match.
    #[error("the renders differ in {what}: {a} and {b}")]
    Mismatch {
        what: &'static str,
        a: String,
        b: String,
    },
    /// An image holds no energy where a ratio or centroid needs some.
    #[error("{what} holds no energy: its luminance sums to {sum}")]
    Empty { what: String, sum: f64 },
}

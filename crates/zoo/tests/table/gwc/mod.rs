//! The General Wrapped Cauchy profile and its fits.

mod fit;
mod minimax;
mod profile;
mod two_lobe;

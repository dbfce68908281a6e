//! The General Wrapped Cauchy angular model: its evaluation and sampling are the runtime's
//! ([`bssrdf_runtime::gwc`], re-exported here); the fits to PBD's azimuthal profile that the
//! bake uses are here: the report's three-anchor fit ([`fit_three_anchors`]), its minimax
//! refinement ([`refine_minimax`]) and the two-lobe fit ([`fit_two_lobes`]).

mod fit;
mod minimax;
mod two_lobe_fit;

pub use bssrdf_runtime::gwc::*;
pub use fit::{fit_anchors, fit_three_anchors, FitBranch, GwcFit, ANCHOR_COS};
pub use minimax::{refine_minimax, MinimaxFit, MINIMAX_MAX_SAMPLES};
pub(crate) use two_lobe_fit::solve_small;
pub use two_lobe_fit::{fit as fit_two_lobes, fit_one_sign as fit_two_lobes_one_sign};

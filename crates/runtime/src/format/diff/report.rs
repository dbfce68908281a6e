//! The types of a comparison's report: the tolerance, metadata differences and the
//! per-quantity statistics of each pair of tables.

use std::fmt;

use serde_json::Value as Json;
use thiserror::Error;

use crate::format::records::AlbedoRange;
use crate::format::spec::{AxisKind, FresnelMoments};

/// How far apart two values may be and still agree: |a − b| ≤ max(absolute,
/// relative · max(|a|, |b|)). The default, both 0, means bit-equal (up to the sign of zero).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Tolerance {
    relative: f64,
    absolute: f64,
}

/// A tolerance that is not a finite number ≥ 0.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[error("{which} tolerance {} is outside its domain: a finite number >= 0", crate::error::Number(*value))]
pub struct ToleranceError {
    /// Which tolerance: `"relative"` or `"absolute"`.
    pub which: &'static str,
    /// The value given.
    pub value: f64,
}

impl Tolerance {
    /// A tolerance of `relative` (dimensionless) and `absolute` (in the values' own units),
    /// both finite and ≥ 0.
    pub fn new(relative: f64, absolute: f64) -> Result<Tolerance, ToleranceError> {
        for (which, value) in [("relative", relative), ("absolute", absolute)] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(ToleranceError { which, value });
            }
        }
        Ok(Tolerance { relative, absolute })
    }

    /// The relative tolerance, dimensionless, ≥ 0.
    pub fn relative(&self) -> f64 {
        self.relative
    }

    /// The absolute tolerance, ≥ 0.
    pub fn absolute(&self) -> f64 {
        self.absolute
    }

    /// Whether `a` and `b` agree: |a − b| ≤ max(absolute, relative · max(|a|, |b|)). A NaN
    /// never agrees.
    pub fn agrees(&self, a: f64, b: f64) -> bool {
        let scale = a.abs().max(b.abs());
        (a - b).abs() <= self.absolute.max(self.relative * scale)
    }
}

/// Which file a table belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// The first file.
    A,
    /// The second file.
    B,
}

impl fmt::Display for Side {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Side::A => "A",
            Side::B => "B",
        })
    }
}

/// What a metadata difference is about. Displays as `file`, `table 0 / 1`, `table 2 of B`,
/// `material skin1` and `provenance tool_version`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Item {
    /// The files as a whole.
    File,
    /// A pair of tables: index `a` in A, index `b` in B.
    Tables { a: usize, b: usize },
    /// A table of one file that pairs with no table of the other.
    Unpaired { side: Side, table: usize },
    /// The material of this name.
    Material(String),
    /// The provenance key of this name.
    Provenance(String),
}

impl fmt::Display for Item {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Item::File => f.write_str("file"),
            Item::Tables { a, b } => write!(f, "table {a} / {b}"),
            Item::Unpaired { side, table } => write!(f, "table {table} of {side}"),
            Item::Material(name) => write!(f, "material {name}"),
            Item::Provenance(key) => write!(f, "provenance {key}"),
        }
    }
}

/// Which field of an [`Item`] differs; [`Field::name`] is its stable spelling.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    /// An unpaired table's counterpart: its η on its side, absent on the other.
    Counterpart,
    /// The table count of a file, or the table index per channel of a material.
    Tables,
    /// Whether a file is zstd-compressed (never compared).
    Compressed,
    /// A table's model (`ModelKind::name`).
    Model,
    /// The Henyey–Greenstein g of a walk-angular table's walk (absent for other models).
    WalkG,
    /// What a walk-angular table tabulates (`WalkComponent::name`; absent for other models).
    WalkComponent,
    /// Whether a table's nodes hold the profile less the analytic ridge, which its lookups add
    /// back (its record's `ridge`, format 1.6).
    Ridge,
    /// A table's Fresnel moments.
    FresnelMoments,
    /// A table's dims (nρ, nθ, nr).
    Dims,
    /// One axis of a table: its node count, first and last node.
    Axis(AxisKind),
    /// Whether a table has the θ-sampling section.
    ThetaCdf,
    /// A table's number of wrapped Cauchy lobes (1, or 2 with `gwc-harmonics`).
    Lobes,
    /// How a two-lobe table's lookups rebuild its lobes (`gwc::Rebuild::name`; compared where
    /// both tables have two lobes).
    Rebuild,
    /// Whether a material of that name is in the file.
    Present,
    /// A material's source.
    Source,
    /// A material's σs, mm⁻¹.
    SigmaS,
    /// A material's σa, mm⁻¹.
    SigmaA,
    /// A material's Henyey–Greenstein g.
    G,
    /// A material's η.
    Eta,
    /// A material's albedo range.
    AlbedoRange,
    /// A provenance value (never compared).
    Value,
}

impl Field {
    /// The field's name in reports: `counterpart`, `tables`, `compressed`, `model`, `walk_g`,
    /// `walk_component`, `ridge`, `fresnel_moments`, `dims`, `axis-rho`, `axis-theta`,
    /// `axis-r`, `theta-cdf`, `lobes`, `rebuild`, `present`, `source`, `sigma_s`, `sigma_a`,
    /// `g`, `eta`, `albedo_range`, `value`.
    pub fn name(self) -> &'static str {
        match self {
            Field::Counterpart => "counterpart",
            Field::Tables => "tables",
            Field::Compressed => "compressed",
            Field::Model => "model",
            Field::WalkG => "walk_g",
            Field::WalkComponent => "walk_component",
            Field::Ridge => "ridge",
            Field::FresnelMoments => "fresnel_moments",
            Field::Dims => "dims",
            Field::Axis(AxisKind::Rho) => "axis-rho",
            Field::Axis(AxisKind::Theta) => "axis-theta",
            Field::Axis(AxisKind::R) => "axis-r",
            Field::ThetaCdf => "theta-cdf",
            Field::Lobes => "lobes",
            Field::Rebuild => "rebuild",
            Field::Present => "present",
            Field::Source => "source",
            Field::SigmaS => "sigma_s",
            Field::SigmaA => "sigma_a",
            Field::G => "g",
            Field::Eta => "eta",
            Field::AlbedoRange => "albedo_range",
            Field::Value => "value",
        }
    }
}

/// An axis as a difference names it: node count, first and last node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisSummary {
    /// Number of nodes.
    pub nodes: usize,
    /// The first node, if any.
    pub first: Option<f32>,
    /// The last node, if any.
    pub last: Option<f32>,
}

impl AxisSummary {
    pub(super) fn of(axis: &[f32]) -> AxisSummary {
        AxisSummary {
            nodes: axis.len(),
            first: axis.first().copied(),
            last: axis.last().copied(),
        }
    }
}

/// The value of a [`Field`] in one file.
#[derive(Debug, Clone, PartialEq)]
pub enum MetaValue {
    /// Not in this file (a table without counterpart, a provenance key only the other has).
    Absent,
    /// A flag: a section or material present, a file compressed.
    Bool(bool),
    /// A count: tables of a file, lobes of a table.
    Count(usize),
    /// A number: the η of a table or material, the g of a table's walk.
    Number(f64),
    /// A table's dims (nρ, nθ, nr).
    Dims([usize; 3]),
    /// A table's Fresnel moments.
    Fresnel(FresnelMoments),
    /// A table's axis.
    Axis(AxisSummary),
    /// A text: a material's source, a table's model, walk component or rebuild.
    Text(String),
    /// One value per RGB channel (σs, σa in mm⁻¹; g).
    PerChannel([f64; 3]),
    /// A material's table index per RGB channel.
    TableIndices([u32; 3]),
    /// A material's albedo range, if it has one.
    AlbedoRange(Option<AlbedoRange>),
    /// A provenance value.
    Json(Json),
}

/// One metadata difference: what, which field, and its value in each file.
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    /// What differs.
    pub item: Item,
    /// Which of its fields.
    pub field: Field,
    /// The value in A.
    pub a: MetaValue,
    /// The value in B.
    pub b: MetaValue,
}

/// One quantity compared value by value: a section, or one component of an interleaved one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// E of `gwc-params`.
    GwcE,
    /// E_β of `gwc-params`.
    GwcEBeta,
    /// c of `gwc-params`.
    GwcC,
    /// `radial-cdf`.
    RadialCdf,
    /// `theta-cdf`, over (ρ′, θ) only.
    ThetaCdf,
    /// rμ₃ of `gwc-harmonics`.
    HarmonicMu3,
    /// rμ₄ of `gwc-harmonics`.
    HarmonicMu4,
}

impl Quantity {
    /// The name in reports: `gwc-params E`, `gwc-params E_beta`, `gwc-params c`,
    /// `radial-cdf`, `theta-cdf`, `gwc-harmonics r*mu3`, `gwc-harmonics r*mu4`.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::GwcE => "gwc-params E",
            Quantity::GwcEBeta => "gwc-params E_beta",
            Quantity::GwcC => "gwc-params c",
            Quantity::RadialCdf => "radial-cdf",
            Quantity::ThetaCdf => "theta-cdf",
            Quantity::HarmonicMu3 => "gwc-harmonics r*mu3",
            Quantity::HarmonicMu4 => "gwc-harmonics r*mu4",
        }
    }

    /// How many axes the quantity is tabulated over: 2 for `theta-cdf` (ρ′, θ), else 3.
    pub fn dims(self) -> usize {
        if self == Quantity::ThetaCdf {
            2
        } else {
            3
        }
    }
}

/// Where a compared value is: its node indices in A and in B (ρ′, θ, r; the third is 0 for a
/// 2-D quantity), the node's axis values and the two values.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Location {
    /// Node indices (ρ′, θ, r) in A.
    pub index_a: [usize; 3],
    /// Node indices (ρ′, θ, r) in B.
    pub index_b: [usize; 3],
    /// Reduced albedo ρ′ of the node.
    pub rho: f64,
    /// Incidence angle θ of the node, radians.
    pub theta: f64,
    /// Radius r of the node, reduced mean free paths (0 for a 2-D quantity).
    pub r: f64,
    /// The value in A.
    pub a: f64,
    /// The value in B.
    pub b: f64,
}

/// Statistics of one quantity of a pair of tables over their common nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct QuantityDiff {
    quantity: Quantity,
    count: usize,
    sum_abs: f64,
    sum_rel: f64,
    max_abs: Option<(f64, Location)>,
    max_rel: Option<(f64, Location)>,
    outside: usize,
}

impl QuantityDiff {
    pub(super) fn new(quantity: Quantity) -> QuantityDiff {
        QuantityDiff {
            quantity,
            count: 0,
            sum_abs: 0.0,
            sum_rel: 0.0,
            max_abs: None,
            max_rel: None,
            outside: 0,
        }
    }

    /// Adds one pair of values at `at` (whose `a` and `b` it fills in).
    pub(super) fn add(&mut self, a: f32, b: f32, at: Location, tolerance: Tolerance) {
        let (a, b) = (f64::from(a), f64::from(b));
        let abs = (a - b).abs();
        let rel = if abs == 0.0 {
            0.0
        } else {
            abs / a.abs().max(b.abs())
        };
        let at = Location { a, b, ..at };
        self.count += 1;
        self.sum_abs += abs;
        self.sum_rel += rel;
        // The first of equal maxima is kept; a NaN never becomes the max.
        let record = |max: &mut Option<(f64, Location)>, value: f64| {
            if value > max.map_or(-1.0, |(m, _)| m) {
                *max = Some((value, at));
            }
        };
        record(&mut self.max_abs, abs);
        record(&mut self.max_rel, rel);
        if !tolerance.agrees(a, b) {
            self.outside += 1;
        }
    }

    fn mean(&self, sum: f64) -> f64 {
        if self.count == 0 {
            0.0
        } else {
            sum / self.count as f64
        }
    }

    /// The quantity compared.
    pub fn quantity(&self) -> Quantity {
        self.quantity
    }

    /// How many values were compared (0 when the tables share no node).
    pub fn count(&self) -> usize {
        self.count
    }

    /// Largest |a − b|, in the quantity's units (0 when nothing was compared).
    pub fn max_abs(&self) -> f64 {
        self.max_abs.map_or(0.0, |(m, _)| m)
    }

    /// Mean |a − b| over the compared values (0 when nothing was compared).
    pub fn mean_abs(&self) -> f64 {
        self.mean(self.sum_abs)
    }

    /// Largest relative difference |a − b| / max(|a|, |b|) (0 when nothing was compared).
    pub fn max_rel(&self) -> f64 {
        self.max_rel.map_or(0.0, |(m, _)| m)
    }

    /// Mean relative difference over the compared values (0 when nothing was compared).
    pub fn mean_rel(&self) -> f64 {
        self.mean(self.sum_rel)
    }

    /// Where the largest |a − b| is (the first such value in index order); `None` when
    /// nothing was compared.
    pub fn max_abs_at(&self) -> Option<&Location> {
        self.max_abs.as_ref().map(|(_, at)| at)
    }

    /// Where the largest relative difference is (the first such value in index order);
    /// `None` when nothing was compared.
    pub fn max_rel_at(&self) -> Option<&Location> {
        self.max_rel.as_ref().map(|(_, at)| at)
    }

    /// How many values do not agree within the tolerance.
    pub fn outside_tolerance(&self) -> usize {
        self.outside
    }
}

/// The value comparison of one pair of tables.
#[derive(Debug, Clone, PartialEq)]
pub struct TableDiff {
    pub(super) a: usize,
    pub(super) b: usize,
    pub(super) eta: f64,
    pub(super) common_dims: [usize; 3],
    pub(super) quantities: Vec<QuantityDiff>,
}

impl TableDiff {
    /// Index of the table in A.
    pub fn a(&self) -> usize {
        self.a
    }

    /// Index of the table in B.
    pub fn b(&self) -> usize {
        self.b
    }

    /// η of the pair (the tables pair only when it is equal).
    pub fn eta(&self) -> f64 {
        self.eta
    }

    /// How many nodes of each axis (ρ′, θ, r) the two tables share.
    pub fn common_dims(&self) -> [usize; 3] {
        self.common_dims
    }

    /// The quantities compared, in order: E, E_β, c, `radial-cdf` always (with a count of 0
    /// when no node is shared), then `theta-cdf`, rμ₃ and rμ₄ where values of them were
    /// compared (both tables have the section).
    pub fn quantities(&self) -> &[QuantityDiff] {
        &self.quantities
    }

    /// How many values were compared, over all quantities.
    pub fn values_compared(&self) -> usize {
        self.quantities.iter().map(QuantityDiff::count).sum()
    }

    /// How many values do not agree within the tolerance, over all quantities.
    pub fn outside_tolerance(&self) -> usize {
        self.quantities
            .iter()
            .map(QuantityDiff::outside_tolerance)
            .sum()
    }
}

/// Everything [`compare`](super::compare) finds.
#[derive(Debug, Clone, PartialEq)]
pub struct LibraryDiff {
    pub(super) tolerance: Tolerance,
    pub(super) differences: Vec<Difference>,
    pub(super) not_compared: Vec<Difference>,
    pub(super) tables: Vec<TableDiff>,
}

impl LibraryDiff {
    /// The tolerance the values were compared with.
    pub fn tolerance(&self) -> Tolerance {
        self.tolerance
    }

    /// The metadata differences, in order: tables of A, then of B, without a counterpart; the
    /// table count; per pair of tables its fields; per material of A its presence in B or its
    /// fields; materials only in B.
    pub fn differences(&self) -> &[Difference] {
        &self.differences
    }

    /// What differs but is not compared: provenance keys (in key order), then compression.
    pub fn not_compared(&self) -> &[Difference] {
        &self.not_compared
    }

    /// The value comparison of each pair of tables, in the order of A's tables.
    pub fn tables(&self) -> &[TableDiff] {
        &self.tables
    }

    /// How many values do not agree within the tolerance, over all pairs of tables.
    pub fn outside_tolerance(&self) -> usize {
        self.tables.iter().map(TableDiff::outside_tolerance).sum()
    }

    /// Whether the files agree: no metadata difference and every value within tolerance.
    pub fn within_tolerance(&self) -> bool {
        self.differences.is_empty() && self.outside_tolerance() == 0
    }
}

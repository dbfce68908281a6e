//! Tables in library files: conversion between a baked [`AngularTable`] and the file format's
//! table records, and zero-copy lookups through a mapped or read [`format::Library`].

use super::{walk_albedo_power, AlbedoPower, AngularTable, Axes, TableError, TableRef};
use crate::format::{self, AxisKind, FresnelMoments, ModelKind, TableData};
use crate::fresnel::Moments;

impl From<Moments> for FresnelMoments {
    fn from(m: Moments) -> Self {
        match m {
            Moments::Exact => FresnelMoments::Exact,
            Moments::Pbrt => FresnelMoments::PbrtPolynomial,
        }
    }
}

impl From<FresnelMoments> for Moments {
    fn from(m: FresnelMoments) -> Self {
        match m {
            FresnelMoments::Exact => Moments::Exact,
            FresnelMoments::PbrtPolynomial => Moments::Pbrt,
        }
    }
}

impl AngularTable {
    /// The table as the file format stores it (axes rounded to f32: the bake already baked at
    /// the f32 node values, so nothing changes).
    pub fn to_table_data(&self) -> TableData {
        let axis = |n: &crate::catmull_rom::Nodes| n.as_slice().iter().map(|&x| x as f32).collect();
        TableData {
            model: match self.walk {
                Some(_) => ModelKind::WalkAngular,
                None => ModelKind::PbdAngular,
            },
            walk: self.walk,
            ridge: self.ridge,
            eta: self.eta,
            fresnel: self.moments.into(),
            rho: axis(self.axes.rho()),
            theta: axis(self.axes.theta()),
            r: axis(self.axes.r()),
            gwc: self.params.clone(),
            cdf: self.radial_cdf.clone(),
            theta_cdf: self.theta_cdf.clone(),
            harmonics: self.harmonics.clone(),
            rebuild: self.rebuild,
        }
    }
}

/// A table of a library file, ready for lookups: its axes (converted to f64 once) and its
/// arrays borrowed from the file's map or buffer.
#[derive(Debug)]
pub struct FileTable<'a> {
    table: format::Table<'a>,
    axes: Axes,
    moments: Moments,
}

impl<'a> FileTable<'a> {
    /// Prepares lookups in table `table` of an open library.
    pub fn new(table: format::Table<'a>) -> Result<Self, TableError> {
        let axis = |kind| {
            table
                .axis(kind)
                .iter()
                .map(|&v| f64::from(v))
                .collect::<Vec<f64>>()
        };
        for kind in [AxisKind::Rho, AxisKind::Theta, AxisKind::R] {
            let len = table.axis(kind).len();
            if len < 2 {
                let axis = kind.name();
                return Err(TableError::AxisTooShort { axis, len });
            }
        }
        let axes = Axes::new(
            axis(AxisKind::Rho),
            axis(AxisKind::Theta),
            axis(AxisKind::R),
        )
        .map_err(|_| TableError::Axes)?
        .with_albedo_power(table.walk().map_or(AlbedoPower::Square, walk_albedo_power));
        let moments = table.fresnel().into();
        let file_table = Self {
            table,
            axes,
            moments,
        };
        file_table.view()?;
        Ok(file_table)
    }

    /// The lookup view (cheap: borrows the file's arrays), with the record's ridge kind.
    pub fn view(&self) -> Result<TableRef<'_>, TableError> {
        let view = TableRef::new(
            self.table.eta(),
            self.moments,
            &self.axes,
            self.table.gwc_params(),
            self.table.radial_cdf(),
            self.table.theta_cdf(),
        )?
        .with_ridge(self.table.ridge());
        match self.table.harmonics() {
            Some(harmonics) => Ok(view
                .with_harmonics(harmonics)?
                .with_rebuild(self.table.rebuild())),
            None => Ok(view),
        }
    }

    /// The format's record of this table.
    pub fn record(&self) -> &format::Table<'a> {
        &self.table
    }

    /// Fresnel moments the table was baked with.
    pub fn moments(&self) -> Moments {
        self.moments
    }

    /// Copies the table into memory, with its walk if it is walk-angular and its ridge kind.
    pub fn to_owned_table(&self) -> Result<AngularTable, TableError> {
        let view = self.view()?;
        let table = AngularTable::from_parts(
            view.eta(),
            self.moments,
            self.axes.clone(),
            self.table.gwc_params().to_vec(),
            self.table.radial_cdf().to_vec(),
            self.table.theta_cdf().map(<[f32]>::to_vec),
        )?
        .with_ridge(self.table.ridge());
        let table = match self.table.harmonics() {
            Some(harmonics) => table.with_harmonics_by(harmonics.to_vec(), self.table.rebuild())?,
            None => table,
        };
        Ok(match self.table.walk() {
            Some(walk) => table.with_walk(walk),
            None => table,
        })
    }
}

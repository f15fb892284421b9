//! The training domain of a mapping: where in feature space a prediction is backed by
//! training rows, so that a prediction outside it is flagged instead of silently returning
//! the edge of the training range (boosted trees are constant beyond their last split).
//!
//! A row is inside when both hold:
//! 1. every feature lies within its training range `[min, max]`;
//! 2. its distance to the nearest training row, in the domain's coordinates, is at most
//!    [`TrainingDomain::threshold`].
//!
//! Coordinates: each feature is min-max scaled on the training rows; a feature whose
//! training values are all positive and span more than [`LOG_SPAN`] (J and Delta_v: bins near
//! a velocity extremum have J near 0, Delta_v spikes where u_inf crosses 0) is scaled on its
//! logarithm, so that a factor of two counts the same at small and large values. The
//! distance to a velocity extremum, d_ext, is the exception: linear, its range from 0
//! ([`FeatureAxis::linear_from_zero`]).
//!
//! Scene-level features: a feature that is the same in every row of each training
//! simulation (the volume fraction phi) is a parameter of the scene that the grid samples at
//! a few levels. It is checked by range only and left out of the distance: between two of
//! its levels the distance would be set by the grid's spacing, while the nearest rows of
//! other simulations, which set the threshold (below), mostly share a level; a flow at
//! phi = 0.54 between training levels 0.53 and 0.58 would be called outside however well
//! its local state is covered.
//!
//! Threshold: for every training row, the distance to the nearest training row of *another*
//! simulation (group); the threshold is the [`THRESHOLD_QUANTILE`] quantile of those
//! distances. A new flow is thus called inside when it lies as close to the training set
//! as 95 % of the training simulations' bins lie to the other simulations. Taking the
//! distance to other simulations (not to any row) matters: neighbouring bins of one profile
//! are almost always close to each other and would make the threshold meaninglessly small.

use std::collections::HashMap;

use ndarray::{ArrayView1, ArrayView2, Axis};
use rayon::prelude::*;
use schema::Fingerprint;
use serde::{Deserialize, Serialize};

use crate::data::samples::Samples;
use crate::data::scaling::Range;
use crate::error::{Result, SurrogateError};
use schema::columns as col;

/// Ratio `max / min` of a positive feature beyond which it is scaled on its logarithm.
pub const LOG_SPAN: f64 = 100.0;
/// Quantile of the leave-one-simulation-out nearest-neighbour distances taken as threshold.
pub const THRESHOLD_QUANTILE: f64 = 0.95;

/// How one feature is mapped to its domain coordinate in [0, 1] over the training rows.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FeatureAxis {
    /// Training range of the feature, in its original units.
    pub range: Range,
    /// Whether the coordinate is the scaled logarithm of the feature.
    pub log: bool,
    /// Whether the feature is a parameter of the scene (the same in every row of each
    /// training simulation, like the volume fraction phi): checked by range only, left out
    /// of the distance.
    #[serde(default)]
    pub scene_level: bool,
}

impl FeatureAxis {
    /// The axis of `column`, whose rows belong to the simulations `groups`.
    fn fit(column: ArrayView1<f64>, groups: &[String]) -> Self {
        let range = Range {
            min: column.fold(f64::INFINITY, |a, &b| a.min(b)),
            max: column.fold(f64::NEG_INFINITY, |a, &b| a.max(b)),
        };
        let log = range.min > 0.0 && range.max > LOG_SPAN * range.min;
        let mut value_of_group: HashMap<&str, f64> = HashMap::new();
        let scene_level = column
            .iter()
            .zip(groups)
            .all(|(&x, g)| *value_of_group.entry(g.as_str()).or_insert(x) == x);
        FeatureAxis {
            range,
            log,
            scene_level,
        }
    }

    /// The axis of the distance to a velocity extremum, d_ext: linear, from 0. Every
    /// training profile has bins at all distances down to its extrema's, and a bin centred on
    /// an extremum (d_ext = 0, as a symmetric forcing places it) is no extrapolation; on a log
    /// axis it would lie infinitely far below the range.
    fn linear_from_zero(self) -> Self {
        FeatureAxis {
            range: Range {
                min: self.range.min.min(0.0),
                max: self.range.max,
            },
            log: false,
            ..self
        }
    }

    /// The coordinate of value `x`: 0 at the training minimum, 1 at the maximum (a constant
    /// feature maps to 0); values outside the range map outside [0, 1]. A non-positive value
    /// on a log axis lies infinitely far below the range. A scene-level feature maps to 0.
    fn coordinate(&self, x: f64) -> f64 {
        if self.scene_level {
            return 0.0;
        }
        let (lo, hi, v) = if self.log {
            if x <= 0.0 {
                return f64::NEG_INFINITY;
            }
            (self.range.min.ln(), self.range.max.ln(), x.ln())
        } else {
            (self.range.min, self.range.max, x)
        };
        if hi > lo {
            (v - lo) / (hi - lo)
        } else {
            v - lo
        }
    }

    fn contains(&self, x: f64) -> bool {
        x >= self.range.min && x <= self.range.max
    }
}

/// Where a row stands relative to the training domain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DomainCheck {
    /// Every feature within its training range.
    pub in_range: bool,
    /// Distance to the nearest training row divided by the threshold (<= 1 is near enough).
    pub distance: f64,
}

impl DomainCheck {
    /// Inside the training domain: in range and near enough.
    pub fn inside(&self) -> bool {
        self.in_range && self.distance <= 1.0
    }
}

/// The training rows of a mapping in domain coordinates, with the distance threshold.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainingDomain {
    /// The feature of each axis: a domain read beside a model must be of its features.
    pub features: Vec<String>,
    /// FNV-1a 64 hash of the training source's bytes (16 hex digits), as in the model's
    /// sidecar: a domain read beside a model must be of its training rows.
    pub training_fnv1a_64: Fingerprint,
    /// One axis per feature, in the model's feature order.
    pub axes: Vec<FeatureAxis>,
    /// Leave-one-simulation-out nearest-neighbour distance quantile (domain coordinates).
    pub threshold: f64,
    /// Training rows in domain coordinates, row after row (`axes.len()` numbers each).
    pub points: Vec<f64>,
}

impl TrainingDomain {
    /// The domain of `samples`' features. Needs rows of at least two simulations (the
    /// threshold compares simulations with each other).
    pub fn fit(samples: &Samples) -> Result<Self> {
        let features = samples.features.view();
        let groups = &samples.groups;
        let axes: Vec<FeatureAxis> = features
            .axis_iter(Axis(1))
            .zip(&samples.feature_names)
            .map(|(column, name)| {
                let axis = FeatureAxis::fit(column, groups);
                if name == col::EXTREMUM_DISTANCE {
                    axis.linear_from_zero()
                } else {
                    axis
                }
            })
            .collect();
        let points = coordinates(&axes, features);
        let n_features = axes.len();
        let mut nearest: Vec<f64> = (0..samples.n_rows())
            .into_par_iter()
            .map(|i| {
                let p = &points[i * n_features..(i + 1) * n_features];
                points
                    .chunks_exact(n_features)
                    .zip(groups)
                    .filter(|(_, g)| *g != &groups[i])
                    .map(|(q, _)| squared_distance(p, q))
                    .fold(f64::INFINITY, f64::min)
                    .sqrt()
            })
            .collect();
        if nearest.iter().any(|d| d.is_infinite()) {
            return Err(SurrogateError::InvalidArgument(format!(
                "the training domain of {} needs rows of at least two simulations",
                samples.source_name
            )));
        }
        nearest.sort_by(f64::total_cmp);
        let rank = ((nearest.len() - 1) as f64 * THRESHOLD_QUANTILE).round() as usize;
        // A threshold of 0 (duplicated simulations) would call every new row outside.
        let threshold = nearest[rank].max(f64::EPSILON);
        Ok(TrainingDomain {
            features: samples.feature_names.clone(),
            training_fnv1a_64: samples.source_fingerprint,
            axes,
            threshold,
            points,
        })
    }

    /// Whether each row of `features` (rows x features, in the model's order) lies inside
    /// ([`DomainCheck::inside`]).
    pub fn inside(&self, features: ArrayView2<f64>) -> Result<Vec<bool>> {
        Ok(self
            .check(features)?
            .iter()
            .map(DomainCheck::inside)
            .collect())
    }

    /// The rows of `features` (rows x features, in the model's order) in the domain's
    /// coordinates, row after row: the space of [`TrainingDomain::threshold`] (a scene-level
    /// feature's coordinate is 0).
    pub fn coordinates(&self, features: ArrayView2<f64>) -> Result<Vec<f64>> {
        if features.ncols() != self.axes.len() {
            return Err(SurrogateError::InvalidArgument(format!(
                "the training domain has {} features, the rows {}",
                self.axes.len(),
                features.ncols()
            )));
        }
        Ok(coordinates(&self.axes, features))
    }

    /// The check of each row of `features` (rows x features, in the model's order).
    pub fn check(&self, features: ArrayView2<f64>) -> Result<Vec<DomainCheck>> {
        let n_features = self.axes.len();
        if features.ncols() != n_features {
            return Err(SurrogateError::InvalidArgument(format!(
                "the training domain has {n_features} features, the rows {}",
                features.ncols()
            )));
        }
        let coords = coordinates(&self.axes, features);
        Ok(features
            .axis_iter(Axis(0))
            .zip(coords.chunks_exact(n_features))
            .map(|(row, p)| DomainCheck {
                in_range: row.iter().zip(&self.axes).all(|(&x, a)| a.contains(x)),
                distance: self
                    .points
                    .chunks_exact(n_features)
                    .map(|q| squared_distance(p, q))
                    .fold(f64::INFINITY, f64::min)
                    .sqrt()
                    / self.threshold,
            })
            .collect())
    }
}

/// Rows of `features` in the domain coordinates of `axes`, row after row.
fn coordinates(axes: &[FeatureAxis], features: ArrayView2<f64>) -> Vec<f64> {
    let mut out = Vec::with_capacity(features.len());
    for row in features.axis_iter(Axis(0)) {
        out.extend(row.iter().zip(axes).map(|(&x, a)| a.coordinate(x)));
    }
    out
}

fn squared_distance(p: &[f64], q: &[f64]) -> f64 {
    p.iter().zip(q).map(|(a, b)| (a - b) * (a - b)).sum()
}

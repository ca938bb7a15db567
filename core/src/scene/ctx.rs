//! The context of the scene's checks (`validate.rs`, and the checks of its parts:
//! `motion.rs`, `wave.rs`, `zones.rs`): the scene's origin for the error, its dimension, and
//! the checks every part shares (a vector's length, a positive number, a box in the domain).

use super::format::Domain;
use super::scheme::{single_precision, Rule};
use super::SceneError;

/// A check's result.
pub(super) type R = Result<(), SceneError>;

/// Where a check is (the scene's origin, for the error) and the scene's dimension.
pub(super) struct Ctx<'a> {
    origin: &'a str,
    pub(super) dim: usize,
}

impl<'a> Ctx<'a> {
    pub(super) fn new(origin: &'a str, dim: usize) -> Ctx<'a> {
        Ctx { origin, dim }
    }

    pub(super) fn err(&self, field: impl Into<String>, reason: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            origin: self.origin.to_string(),
            field: field.into(),
            reason: reason.into(),
        }
    }

    pub(super) fn vec(&self, field: &str, v: &[f64]) -> R {
        if v.len() != self.dim {
            return Err(self.err(
                field,
                format!(
                    "expected {} numbers (dimension = {}), found {}",
                    self.dim,
                    self.dim,
                    v.len()
                ),
            ));
        }
        for (i, &x) in v.iter().enumerate() {
            single_precision(x).map_err(|why| self.err(format!("{field}[{i}]"), why))?;
        }
        Ok(())
    }

    pub(super) fn opt_vec(&self, field: &str, v: &Option<Vec<f64>>) -> R {
        match v {
            Some(v) => self.vec(field, v),
            None => Ok(()),
        }
    }

    pub(super) fn corners(&self, field: &str, min: &[f64], max: &[f64]) -> R {
        self.vec(&format!("{field}.min"), min)?;
        self.vec(&format!("{field}.max"), max)?;
        for a in 0..self.dim {
            if min[a] >= max[a] {
                return Err(self.err(
                    format!("{field}.max"),
                    format!(
                        "max[{a}] = {} is not greater than min[{a}] = {}",
                        max[a], min[a]
                    ),
                ));
            }
        }
        Ok(())
    }

    pub(super) fn positive(&self, field: &str, x: f64) -> R {
        Rule::Positive
            .check(Some(x))
            .map_err(|r| self.err(field, r.reason))
    }

    pub(super) fn non_negative(&self, field: &str, x: f64) -> R {
        Rule::NonNegative
            .check(Some(x))
            .map_err(|r| self.err(field, r.reason))
    }

    /// The box [lo, hi] (first `dim` axes) lies inside the domain.
    pub(super) fn inside(&self, field: &str, what: &str, lo: &[f64], hi: &[f64], d: &Domain) -> R {
        for a in 0..self.dim {
            let tol = 1e-9 * (d.max[a] - d.min[a]);
            if lo[a] < d.min[a] - tol {
                return Err(self.err(
                    field,
                    format!(
                        "{what} reaches {} on axis {a}, below domain.min[{a}] = {}",
                        fmt(lo[a]),
                        d.min[a]
                    ),
                ));
            }
            if hi[a] > d.max[a] + tol {
                return Err(self.err(
                    field,
                    format!(
                        "{what} reaches {} on axis {a}, beyond domain.max[{a}] = {}",
                        fmt(hi[a]),
                        d.max[a]
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// A number as a check's message prints it (to 1e-9).
pub(super) fn fmt(x: f64) -> String {
    format!("{}", (x * 1e9).round() / 1e9)
}

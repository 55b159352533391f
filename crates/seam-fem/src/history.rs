//! Load history of a quasi-static solve: the pseudo-time t ∈ (0, 1], the
//! times a problem is solved at ([`LoadSteps`]), how each load and support
//! follows t ([`Amplitude`]), and values that vary in space and time
//! ([`Value`]).
//!
//! A load or support with the value v(x, t) and the amplitude a(t) prescribes
//! a(t) · v(x, t) at time t; the default amplitude is the ramp a(t) = t, so
//! that a problem of one step (t = 1) sees its values as given.

use seam::Point3;
use std::fmt;
use std::sync::Arc;

/// Why a load history or an amplitude cannot be used.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum HistoryError {
    /// Zero steps.
    #[error("steps must be at least 1")]
    NoSteps,
    /// Times that are not increasing, not in (0, 1], or not ending at 1.
    #[error("times {0}")]
    Times(String),
    /// An amplitude table that is empty, not increasing in t, outside
    /// [0, 1] or not finite.
    #[error("{0}")]
    Amplitude(String),
}

/// The pseudo-times t₁ < t₂ < … < t_N = 1 at which a problem is solved,
/// each step starting from the state of the one before.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadSteps {
    times: Vec<f64>,
}

impl Default for LoadSteps {
    /// One step, t = 1.
    fn default() -> Self {
        LoadSteps { times: vec![1.0] }
    }
}

impl LoadSteps {
    /// `steps` equal increments: t_k = k / steps.
    ///
    /// # Errors
    /// [`HistoryError::NoSteps`] for 0.
    pub fn equal(steps: usize) -> Result<LoadSteps, HistoryError> {
        if steps == 0 {
            return Err(HistoryError::NoSteps);
        }
        let times = (1..=steps).map(|k| if k == steps { 1.0 } else { k as f64 / steps as f64 }).collect();
        Ok(LoadSteps { times })
    }

    /// The given times.
    ///
    /// # Errors
    /// [`HistoryError::Times`] unless they are finite, strictly increasing,
    /// in (0, 1] and end at 1.
    pub fn at(times: Vec<f64>) -> Result<LoadSteps, HistoryError> {
        let fail = |why: String| Err(HistoryError::Times(why));
        let Some(&last) = times.last() else {
            return fail("must hold at least one time (the last one 1.0)".into());
        };
        if let Some(t) = times.iter().find(|t| !(t.is_finite() && **t > 0.0 && **t <= 1.0)) {
            return fail(format!("must lie in (0, 1]: {t} does not"));
        }
        if let Some(w) = times.windows(2).find(|w| w[1] <= w[0]) {
            return fail(format!("must increase: {} follows {}", w[1], w[0]));
        }
        if last != 1.0 {
            return fail(format!("must end at 1.0 (the full load), not {last}"));
        }
        Ok(LoadSteps { times })
    }

    /// The times, increasing, the last one 1.
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// The number of steps.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// Never true (kept for the convention of `len`).
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }
}

/// A factor over pseudo-time, piecewise linear through a table of (t, a)
/// with t increasing in [0, 1], constant before the first and after the
/// last entry (as Abaqus's `*AMPLITUDE`).
#[derive(Clone, Debug, PartialEq)]
pub struct Amplitude {
    table: Vec<[f64; 2]>,
}

impl Default for Amplitude {
    /// The ramp a(t) = t.
    fn default() -> Self {
        Amplitude::ramp()
    }
}

impl Amplitude {
    /// The ramp a(t) = t, the table [[0, 0], [1, 1]].
    pub fn ramp() -> Amplitude {
        Amplitude { table: vec![[0.0, 0.0], [1.0, 1.0]] }
    }

    /// The table `table` of (t, a).
    ///
    /// # Errors
    /// [`HistoryError::Amplitude`] for an empty table, a value that is not
    /// finite, t outside [0, 1], or t not strictly increasing.
    pub fn new(table: Vec<[f64; 2]>) -> Result<Amplitude, HistoryError> {
        let fail = |why: String| Err(HistoryError::Amplitude(why));
        if table.is_empty() {
            return fail("needs at least one [t, factor] pair".into());
        }
        if let Some(e) = table.iter().find(|e| !(e[0].is_finite() && e[1].is_finite())) {
            return fail(format!("entries must be finite: [{}, {}] is not", e[0], e[1]));
        }
        if let Some(e) = table.iter().find(|e| !(0.0..=1.0).contains(&e[0])) {
            return fail(format!("times must lie in [0, 1]: {} does not", e[0]));
        }
        if let Some(w) = table.windows(2).find(|w| w[1][0] <= w[0][0]) {
            return fail(format!("times must increase: {} follows {}", w[1][0], w[0][0]));
        }
        Ok(Amplitude { table })
    }

    /// The table.
    pub fn table(&self) -> &[[f64; 2]] {
        &self.table
    }

    /// Whether it is the default ramp.
    pub fn is_ramp(&self) -> bool {
        *self == Amplitude::ramp()
    }

    /// a(t): a table entry exactly at its t (so the ramp gives 1 at t = 1),
    /// linear between entries, constant outside them.
    pub fn at(&self, t: f64) -> f64 {
        let i = self.table.partition_point(|e| e[0] <= t);
        match i {
            0 => self.table[0][1],
            i if i == self.table.len() || self.table[i - 1][0] == t => self.table[i - 1][1],
            i => {
                let ([t0, a0], [t1, a1]) = (self.table[i - 1], self.table[i]);
                a0 + (a1 - a0) * (t - t0) / (t1 - t0)
            }
        }
    }
}

/// The function of a [`Value::Function`]: the reference position x and the
/// pseudo-time t to a number, or why it has none there.
pub type ValueFn = dyn Fn(Point3, f64) -> Result<f64, String> + Send + Sync;

/// A prescribed scalar (a displacement or traction component): a number, or
/// a function of the reference position and the pseudo-time, with its text
/// for messages and for writing it back.
#[derive(Clone)]
pub enum Value {
    /// The same everywhere and at every time (before the amplitude).
    Number(f64),
    /// v(x, t) and its text.
    Function(String, Arc<ValueFn>),
}

impl fmt::Debug for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Number(v) => write!(f, "{v:?}"),
            Value::Function(text, _) => write!(f, "{text:?}"),
        }
    }
}

impl From<f64> for Value {
    fn from(v: f64) -> Value {
        Value::Number(v)
    }
}

impl Value {
    /// v(x, t).
    ///
    /// # Errors
    /// The function's reason when it has no finite value there.
    pub fn at(&self, x: Point3, t: f64) -> Result<f64, String> {
        match self {
            Value::Number(v) => Ok(*v),
            Value::Function(_, f) => f(x, t),
        }
    }

    /// The number, when it is one.
    pub fn number(&self) -> Option<f64> {
        match self {
            Value::Number(v) => Some(*v),
            Value::Function(..) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn amplitudes_interpolate_and_hold_their_ends() {
        let ramp = Amplitude::ramp();
        assert_eq!(ramp.at(1.0), 1.0);
        assert_eq!(ramp.at(0.25), 0.25);
        let a = Amplitude::new(vec![[0.2, 0.0], [0.5, 1.0], [1.0, 1.0]]).unwrap();
        assert_eq!(a.at(0.0), 0.0);
        assert_eq!(a.at(0.5), 1.0);
        assert!((a.at(0.35) - 0.5).abs() < 1e-15);
        assert_eq!(a.at(1.0), 1.0);
        assert_eq!(Amplitude::new(vec![[0.3, 2.0]]).unwrap().at(0.9), 2.0);
        // a(t_k) is the table's value exactly, whatever the rounding of the slope.
        let b = Amplitude::new(vec![[0.0, 0.1], [0.3, 0.7], [1.0, 0.3]]).unwrap();
        assert_eq!((b.at(0.3), b.at(1.0)), (0.7, 0.3));
    }

    #[test]
    fn bad_tables_and_times_are_named() {
        let bad = [
            (Amplitude::new(vec![]), "needs at least one"),
            (Amplitude::new(vec![[0.5, 0.0], [0.5, 1.0]]), "times must increase: 0.5 follows 0.5"),
            (Amplitude::new(vec![[0.0, 0.0], [1.5, 1.0]]), "times must lie in [0, 1]: 1.5 does not"),
            (Amplitude::new(vec![[0.0, f64::NAN]]), "entries must be finite"),
        ];
        for (r, message) in bad {
            assert!(r.unwrap_err().to_string().contains(message), "{message}");
        }
        assert_eq!(LoadSteps::equal(0).unwrap_err(), HistoryError::NoSteps);
        assert_eq!(LoadSteps::equal(4).unwrap().times(), [0.25, 0.5, 0.75, 1.0]);
        assert_eq!(LoadSteps::equal(3).unwrap().times()[2], 1.0);
        let bad = [
            (vec![0.5, 0.4, 1.0], "must increase: 0.4 follows 0.5"),
            (vec![0.0, 1.0], "must lie in (0, 1]: 0 does not"),
            (vec![0.5, 0.9], "must end at 1.0 (the full load), not 0.9"),
            (vec![], "at least one time"),
        ];
        for (times, message) in bad {
            let e = LoadSteps::at(times).unwrap_err().to_string();
            assert!(e.contains(message), "{e}");
        }
    }
}

//! Expressions in x, y and z (`seam transfer --expr "sin(x)*y + z"`), parsed
//! once by [exmex] and evaluated at points.
//!
//! Before exmex sees it, the text is bounded: at most [`MAX_LEN`] characters and
//! parentheses nested at most [`MAX_DEPTH`] deep, so that no input costs more
//! than a few kilobytes of parsing. Every value is checked: NaN or ±∞ (for
//! example `sqrt(x - 0.5)` at x < 0.5, `1/x` at x = 0) is an error naming the
//! point, never a result.

use exmex::prelude::*;
use seam::Point3;

/// The longest expression text accepted, in bytes.
pub const MAX_LEN: usize = 1000;

/// The deepest nesting of parentheses accepted.
pub const MAX_DEPTH: usize = 32;

/// Why an expression cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ExpressionError {
    /// The text is longer than [`MAX_LEN`].
    #[error("the expression has {len} bytes; at most {MAX_LEN} are accepted")]
    TooLong {
        /// Its length in bytes.
        len: usize,
    },
    /// Parentheses nest deeper than [`MAX_DEPTH`].
    #[error("the expression '{text}' nests parentheses {depth} deep; at most {MAX_DEPTH} are accepted")]
    TooDeep {
        /// The expression.
        text: String,
        /// Its deepest nesting.
        depth: usize,
    },
    /// exmex cannot parse it.
    #[error("the expression '{text}' does not parse: {message}")]
    Parse {
        /// The expression.
        text: String,
        /// exmex's reason, on one line.
        message: String,
    },
    /// It uses a variable other than x, y and z.
    #[error("the expression '{text}' uses '{name}'; only x, y and z are known")]
    UnknownVariable {
        /// The expression.
        text: String,
        /// The unknown variable.
        name: String,
    },
    /// exmex cannot evaluate it at a point.
    #[error("the expression '{text}' cannot be evaluated at {}: {message}", coordinates(*.point))]
    Eval {
        /// The expression.
        text: String,
        /// The point.
        point: Point3,
        /// exmex's reason, on one line.
        message: String,
    },
    /// Its value at a point is NaN or infinite.
    #[error("the expression '{text}' is {value} at {}{}", coordinates(*.point), index.map_or(String::new(), |i| format!(" (point {i}, 0-based)")))]
    NotFinite {
        /// The expression.
        text: String,
        /// The point.
        point: Point3,
        /// The value there.
        value: f64,
        /// The point's index in the points [`Expression::sample`] was given.
        index: Option<usize>,
    },
}

fn coordinates(p: Point3) -> String {
    format!("({}, {}, {})", p[0], p[1], p[2])
}

fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// An expression in x, y, z, parsed once.
#[derive(Clone, Debug)]
pub struct Expression {
    text: String,
    expr: FlatEx<f64>,
    /// For each variable of the expression (alphabetical, as exmex orders
    /// them), the coordinate it stands for.
    axes: Vec<usize>,
}

impl Expression {
    /// Parses `text`; its variables must be among x, y and z (any subset, in
    /// any order).
    ///
    /// # Errors
    /// [`ExpressionError::TooLong`], [`ExpressionError::TooDeep`],
    /// [`ExpressionError::Parse`], [`ExpressionError::UnknownVariable`].
    pub fn parse(text: &str) -> Result<Expression, ExpressionError> {
        if text.len() > MAX_LEN {
            return Err(ExpressionError::TooLong { len: text.len() });
        }
        let depth = nesting(text);
        if depth > MAX_DEPTH {
            return Err(ExpressionError::TooDeep { text: text.to_string(), depth });
        }
        let expr = exmex::parse::<f64>(text).map_err(|e| ExpressionError::Parse {
            text: text.to_string(),
            message: one_line(&e.to_string()),
        })?;
        let axes = expr
            .var_names()
            .iter()
            .map(|v| match v.as_str() {
                "x" => Ok(0),
                "y" => Ok(1),
                "z" => Ok(2),
                other => {
                    Err(ExpressionError::UnknownVariable { text: text.to_string(), name: other.to_string() })
                }
            })
            .collect::<Result<Vec<usize>, _>>()?;
        Ok(Expression { text: text.to_string(), expr, axes })
    }

    /// The text it was parsed from.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The value at `p`.
    ///
    /// # Errors
    /// [`ExpressionError::NotFinite`] (without index) when the value is NaN or
    /// infinite; [`ExpressionError::Eval`].
    pub fn at(&self, p: Point3) -> Result<f64, ExpressionError> {
        let mut args = [0.0; 3];
        for (arg, &k) in args.iter_mut().zip(&self.axes) {
            *arg = p[k];
        }
        let value = self.expr.eval(&args[..self.axes.len()]).map_err(|e| ExpressionError::Eval {
            text: self.text.clone(),
            point: p,
            message: one_line(&e.to_string()),
        })?;
        if !value.is_finite() {
            return Err(ExpressionError::NotFinite { text: self.text.clone(), point: p, value, index: None });
        }
        Ok(value)
    }

    /// The values at `points[i]` where `wanted[i]`, 0 elsewhere (points no face
    /// uses need no value, and may lie where the expression is undefined).
    ///
    /// # Errors
    /// As [`Expression::at`], with the index of the first wanted point whose
    /// value is not finite.
    ///
    /// # Panics
    /// If `wanted` is shorter than `points`.
    pub fn sample(&self, points: &[Point3], wanted: &[bool]) -> Result<Vec<f64>, ExpressionError> {
        assert!(wanted.len() >= points.len(), "one `wanted` flag per point");
        points
            .iter()
            .enumerate()
            .map(|(i, &p)| match wanted[i] {
                false => Ok(0.0),
                true => self.at(p).map_err(|e| match e {
                    ExpressionError::NotFinite { text, point, value, .. } => {
                        ExpressionError::NotFinite { text, point, value, index: Some(i) }
                    }
                    other => other,
                }),
            })
            .collect()
    }
}

/// The deepest nesting of parentheses (and brackets) in `text`.
fn nesting(text: &str) -> usize {
    let (mut depth, mut deepest) = (0usize, 0usize);
    for c in text.chars() {
        match c {
            '(' | '[' | '{' => {
                depth += 1;
                deepest = deepest.max(depth);
            }
            ')' | ']' | '}' => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    deepest
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expressions_take_x_y_z_in_any_order_and_subset() {
        let e = Expression::parse("sin(x)*y + z").unwrap();
        assert!((e.at([0.5, 2.0, -1.0]).unwrap() - (0.5f64.sin() * 2.0 - 1.0)).abs() < 1e-15);
        let e = Expression::parse("z - y").unwrap();
        assert_eq!(e.at([9.0, 2.0, 5.0]).unwrap(), 3.0);
        assert_eq!(Expression::parse("2.5").unwrap().at([1.0, 1.0, 1.0]).unwrap(), 2.5);
        assert_eq!(e.text(), "z - y");
    }

    #[test]
    fn bad_expressions_are_named() {
        assert!(matches!(Expression::parse("sin(x"), Err(ExpressionError::Parse { .. })));
        let err = Expression::parse("x + w").unwrap_err().to_string();
        assert_eq!(err, "the expression 'x + w' uses 'w'; only x, y and z are known");
        let long = "x+".repeat(600) + "x";
        assert_eq!(
            Expression::parse(&long).unwrap_err().to_string(),
            "the expression has 1201 bytes; at most 1000 are accepted"
        );
        let deep = "(".repeat(40) + "x" + &")".repeat(40);
        assert!(Expression::parse(&deep)
            .unwrap_err()
            .to_string()
            .ends_with("nests parentheses 40 deep; at most 32 are accepted"));
        let ok = "(".repeat(32) + "x" + &")".repeat(32);
        assert_eq!(Expression::parse(&ok).unwrap().at([3.0, 0.0, 0.0]).unwrap(), 3.0);
    }

    #[test]
    fn non_finite_values_are_errors_naming_the_point() {
        let e = Expression::parse("sqrt(x-0.5)").unwrap();
        let err = e.at([0.0, 1.0, 2.0]).unwrap_err();
        assert!(
            matches!(err, ExpressionError::NotFinite { value, index: None, .. } if value.is_nan()),
            "{err:?}"
        );
        assert_eq!(err.to_string(), "the expression 'sqrt(x-0.5)' is NaN at (0, 1, 2)");
        let points = [[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.25, 0.0, 0.0]];
        // The second point is not wanted: 0 there, and the third fails.
        let err = e.sample(&points, &[true, false, true]).unwrap_err();
        assert_eq!(err.to_string(), "the expression 'sqrt(x-0.5)' is NaN at (0.25, 0, 0) (point 2, 0-based)");
        let values = e.sample(&points[..2], &[true, false]).unwrap();
        assert_eq!(values, [0.5f64.sqrt(), 0.0]);
        let err = Expression::parse("1/x").unwrap().at([0.0; 3]).unwrap_err().to_string();
        assert_eq!(err, "the expression '1/x' is inf at (0, 0, 0)");
    }
}

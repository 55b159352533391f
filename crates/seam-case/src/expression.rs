//! Expressions in x, y and z (`seam transfer --expr "sin(x)*y + 1e-3*z"`),
//! and in the pseudo-time t too for the values of a case's Dirichlet
//! conditions and tractions (`ux = "1e-3*z*t"`), parsed once by [exmex] and
//! evaluated at points.
//!
//! Before exmex sees it, the text is bounded: at most [`MAX_LEN`] characters and
//! parentheses nested at most [`MAX_DEPTH`] deep, so that no input costs more
//! than a few kilobytes of parsing. Then it is read token by token here
//! (numbers in decimal or scientific notation, x, y, z, the [`FUNCTIONS`] and
//! [`CONSTANTS`], `+ - * / ^`, parentheses, commas), so that every mistake is
//! named in our words at its character: an unknown function, a number beyond
//! double precision, a missing operator or operand, unbalanced parentheses, a
//! unary minus before `^` (`-x^2` is −(x²) in mathematics but (−x)² to exmex:
//! refused, asking for parentheses).
//! Every value is checked: NaN or ±∞ (for example `sqrt(x - 0.5)` at x < 0.5,
//! `1/x` at x = 0) is an error naming the point, never a result.

use exmex::prelude::*;
use exmex::{FloatOpsFactory, MatchLiteral};
use seam::Point3;

/// The functions an expression may call, with their number of arguments
/// (exmex's; `log` is `ln`).
pub const FUNCTIONS: &[(&str, usize)] = &[
    ("abs", 1),
    ("signum", 1),
    ("sin", 1),
    ("cos", 1),
    ("tan", 1),
    ("asin", 1),
    ("acos", 1),
    ("atan", 1),
    ("sinh", 1),
    ("cosh", 1),
    ("tanh", 1),
    ("asinh", 1),
    ("acosh", 1),
    ("atanh", 1),
    ("floor", 1),
    ("round", 1),
    ("ceil", 1),
    ("trunc", 1),
    ("fract", 1),
    ("exp", 1),
    ("sqrt", 1),
    ("cbrt", 1),
    ("ln", 1),
    ("log", 1),
    ("log2", 1),
    ("log10", 1),
    ("atan2", 2),
    ("min", 2),
    ("max", 2),
];

/// The named constants an expression may use (π, e, τ).
pub const CONSTANTS: &[&str] = &["PI", "π", "E", "e", "TAU", "τ"];

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
    /// It does not have the form of an expression.
    #[error("the expression '{text}' does not parse at character {position}: {problem}")]
    Parse {
        /// The expression.
        text: String,
        /// Where (1-based, in characters).
        position: usize,
        /// What is wrong there.
        problem: String,
    },
    /// It calls a function that is not one of [`FUNCTIONS`].
    #[error(
        "the expression '{text}' calls '{name}', which is not a known function; the functions are {}",
        function_list()
    )]
    UnknownFunction {
        /// The expression.
        text: String,
        /// The unknown name.
        name: String,
    },
    /// A number beyond the range of double precision, or so small that it
    /// would be 0.
    #[error("the expression '{text}' holds the number {number}, {}", if *.overflow { "beyond double precision (magnitude at most 1.8e308)" } else { "below the smallest double precision number (4.9e-324): it would be 0" })]
    NumberOutOfRange {
        /// The expression.
        text: String,
        /// The number as written.
        number: String,
        /// Too large (else too small).
        overflow: bool,
    },
    /// It uses a variable other than x, y and z (and t, for
    /// [`Expression::parse_in_time`]).
    #[error("the expression '{text}' uses '{name}'; only {} are known", if *.time { "x, y, z and t" } else { "x, y and z" })]
    UnknownVariable {
        /// The expression.
        text: String,
        /// The unknown variable.
        name: String,
        /// Whether t is known.
        time: bool,
    },
    /// exmex cannot evaluate it at a point.
    #[error("the expression '{text}' cannot be evaluated at {}{}: {message}", coordinates(*.point), at_time(*.time))]
    Eval {
        /// The expression.
        text: String,
        /// The point.
        point: Point3,
        /// The pseudo-time, for an expression in t.
        time: Option<f64>,
        /// exmex's reason, on one line.
        message: String,
    },
    /// Its value at a point is NaN or infinite.
    #[error("the expression '{text}' is {value} at {}{}{}", coordinates(*.point), at_time(*.time), index.map_or(String::new(), |i| format!(" (point {i}, 0-based)")))]
    NotFinite {
        /// The expression.
        text: String,
        /// The point.
        point: Point3,
        /// The pseudo-time, for an expression in t.
        time: Option<f64>,
        /// The value there.
        value: f64,
        /// The point's index in the points [`Expression::sample`] was given.
        index: Option<usize>,
    },
}

fn coordinates(p: Point3) -> String {
    format!("({}, {}, {})", p[0], p[1], p[2])
}

fn at_time(t: Option<f64>) -> String {
    t.map_or(String::new(), |t| format!(", t = {t}"))
}

fn function_list() -> String {
    FUNCTIONS.iter().map(|(name, _)| *name).collect::<Vec<_>>().join(", ")
}

fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// An expression in x, y, z (and possibly the pseudo-time t), parsed once.
#[derive(Clone, Debug)]
pub struct Expression {
    text: String,
    expr: FlatEx<f64, FloatOpsFactory<f64>, Numbers>,
    /// For each variable of the expression (alphabetical, as exmex orders
    /// them), what it stands for: a coordinate 0, 1, 2, or 3 for t.
    axes: Vec<usize>,
    /// Whether t is a variable ([`Expression::parse_in_time`]).
    time: bool,
}

impl Expression {
    /// Parses `text`; its variables must be among x, y and z (any subset, in
    /// any order).
    ///
    /// # Errors
    /// [`ExpressionError::TooLong`], [`ExpressionError::TooDeep`],
    /// [`ExpressionError::Parse`], [`ExpressionError::UnknownVariable`],
    /// [`ExpressionError::UnknownFunction`], [`ExpressionError::NumberOutOfRange`].
    pub fn parse(text: &str) -> Result<Expression, ExpressionError> {
        Expression::parse_as(text, false)
    }

    /// Parses `text`, an expression in x, y, z and the pseudo-time t (the
    /// values of a case's Dirichlet conditions and tractions).
    ///
    /// # Errors
    /// As [`Expression::parse`].
    pub fn parse_in_time(text: &str) -> Result<Expression, ExpressionError> {
        Expression::parse_as(text, true)
    }

    fn parse_as(text: &str, time: bool) -> Result<Expression, ExpressionError> {
        if text.len() > MAX_LEN {
            return Err(ExpressionError::TooLong { len: text.len() });
        }
        let depth = nesting(text);
        if depth > MAX_DEPTH {
            return Err(ExpressionError::TooDeep { text: text.to_string(), depth });
        }
        check_syntax(text, time)?;
        // exmex skips spaces only; what it might still refuse is named
        // without its internal wording.
        let spaced: String = text.chars().map(|c| if c.is_whitespace() { ' ' } else { c }).collect();
        let expr = FlatEx::<f64, FloatOpsFactory<f64>, Numbers>::parse(&spaced).map_err(|_| {
            ExpressionError::Parse {
                text: text.to_string(),
                position: 1,
                problem: "not an expression of numbers, x, y, z, + - * / ^, parentheses and functions such as sin(x)"
                    .into(),
            }
        })?;
        let axes = expr
            .var_names()
            .iter()
            .map(|v| match v.as_str() {
                "x" => Ok(0),
                "y" => Ok(1),
                "z" => Ok(2),
                "t" if time => Ok(3),
                other => Err(ExpressionError::UnknownVariable {
                    text: text.to_string(),
                    name: other.to_string(),
                    time,
                }),
            })
            .collect::<Result<Vec<usize>, _>>()?;
        Ok(Expression { text: text.to_string(), expr, axes, time })
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
        self.eval(p, 0.0)
    }

    /// The value at `p` and pseudo-time `t` (of an expression from
    /// [`Expression::parse_in_time`]; other expressions ignore `t`).
    ///
    /// # Errors
    /// As [`Expression::at`], naming t.
    pub fn at_time(&self, p: Point3, t: f64) -> Result<f64, ExpressionError> {
        self.eval(p, t)
    }

    fn eval(&self, p: Point3, t: f64) -> Result<f64, ExpressionError> {
        let all = [p[0], p[1], p[2], t];
        let mut args = [0.0; 4];
        for (arg, &k) in args.iter_mut().zip(&self.axes) {
            *arg = all[k];
        }
        let time = self.time.then_some(t);
        let value = self.expr.eval(&args[..self.axes.len()]).map_err(|e| ExpressionError::Eval {
            text: self.text.clone(),
            point: p,
            time,
            message: one_line(&e.to_string()),
        })?;
        if !value.is_finite() {
            return Err(ExpressionError::NotFinite {
                text: self.text.clone(),
                point: p,
                time,
                value,
                index: None,
            });
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
                    ExpressionError::NotFinite { text, point, time, value, .. } => {
                        ExpressionError::NotFinite { text, point, time, value, index: Some(i) }
                    }
                    other => other,
                }),
            })
            .collect()
    }
}

/// Numbers as exmex reads them here: decimal or scientific notation
/// ([`number_prefix`]).
#[derive(Clone, Debug)]
struct Numbers;

impl MatchLiteral for Numbers {
    fn is_literal(text: &str) -> Option<&str> {
        number_prefix(text)
    }
}

/// The number `text` starts with: digits with at most one `.` (at least one
/// digit), then an optional exponent `e` or `E`, a sign and digits: `2`,
/// `2.5`, `.5`, `1e-3`, `1E+2`.
fn number_prefix(text: &str) -> Option<&str> {
    let b = text.as_bytes();
    let digits = |from: usize| from + b[from..].iter().take_while(|c| c.is_ascii_digit()).count();
    let mut end = digits(0);
    let mut mantissa = end;
    if b.get(end) == Some(&b'.') {
        let after = digits(end + 1);
        mantissa += after - end - 1;
        end = after;
    }
    if mantissa == 0 {
        return None;
    }
    if matches!(b.get(end), Some(b'e' | b'E')) {
        let sign = usize::from(matches!(b.get(end + 1), Some(b'+' | b'-')));
        let exponent = digits(end + 1 + sign);
        if exponent > end + 1 + sign {
            end = exponent;
        }
    }
    Some(&text[..end])
}

/// What a token is, for the checks of [`check_syntax`].
#[derive(Clone, Copy, PartialEq)]
enum Token<'a> {
    Value(&'a str),
    Function(&'a str, usize),
    Operator(char),
    Open,
    Close,
    Comma,
}

impl Token<'_> {
    fn describe(self) -> String {
        match self {
            Token::Value(t) | Token::Function(t, _) => format!("'{t}'"),
            Token::Operator(c) => format!("'{c}'"),
            Token::Open => "'('".into(),
            Token::Close => "')'".into(),
            Token::Comma => "','".into(),
        }
    }
}

/// Reads `text` token by token: every name is x, y, z, a constant or a
/// function, every number fits double precision, operands and operators
/// alternate, parentheses balance and commas separate the two arguments of
/// atan2, min and max.
fn check_syntax(text: &str, time: bool) -> Result<(), ExpressionError> {
    let fail =
        |position: usize, problem: String| ExpressionError::Parse { text: text.into(), position, problem };
    // The open parentheses: (position, the two-argument function called, commas).
    let mut open: Vec<(usize, Option<&str>, usize)> = Vec::new();
    // After an operand (a value or ')'), else where an operand is due.
    let mut after_operand = false;
    let mut previous: Option<Token> = None;
    // A unary minus: its position, the parentheses open at it, and whether
    // its operand is complete (then a '^' would make it ambiguous).
    let mut minus: Option<(usize, usize, bool)> = None;
    let chars: Vec<(usize, char)> = text.char_indices().collect();
    let mut i = 0;
    loop {
        while chars.get(i).is_some_and(|(_, c)| c.is_whitespace()) {
            i += 1;
        }
        let position = i + 1;
        let Some(&(at, c)) = chars.get(i) else { break };
        let rest = &text[at..];
        let (token, len) = if let Some(number) = number_prefix(rest) {
            let value: f64 =
                number.parse().map_err(|_| fail(position, format!("'{number}' is not a number")))?;
            let nonzero = number
                .split(['e', 'E'])
                .next()
                .is_some_and(|m| m.bytes().any(|d| (b'1'..=b'9').contains(&d)));
            if value.is_infinite() || (value == 0.0 && nonzero) {
                return Err(ExpressionError::NumberOutOfRange {
                    text: text.into(),
                    number: number.into(),
                    overflow: value.is_infinite(),
                });
            }
            (Token::Value(number), number.chars().count())
        } else if c.is_alphabetic() || c == '_' {
            let len = rest.chars().take_while(|&c| c.is_alphanumeric() || c == '_').count();
            let end = rest.char_indices().nth(len).map_or(rest.len(), |(e, _)| e);
            let name = &rest[..end];
            let next = rest[end..].trim_start().chars().next();
            let token = match FUNCTIONS.iter().find(|(f, _)| *f == name) {
                Some(&(f, n)) => Token::Function(f, n),
                None if ["x", "y", "z"].contains(&name)
                    || (time && name == "t")
                    || CONSTANTS.contains(&name) =>
                {
                    Token::Value(name)
                }
                None if next == Some('(') => {
                    return Err(ExpressionError::UnknownFunction { text: text.into(), name: name.into() })
                }
                None => {
                    return Err(ExpressionError::UnknownVariable {
                        text: text.into(),
                        name: name.into(),
                        time,
                    })
                }
            };
            (token, len)
        } else {
            let token = match c {
                '+' | '-' | '*' | '/' | '^' => Token::Operator(c),
                '(' => Token::Open,
                ')' => Token::Close,
                ',' => Token::Comma,
                _ => return Err(fail(position, format!("'{c}' is not part of an expression"))),
            };
            (token, 1)
        };
        // '-x^2' is −(x²) in mathematics, (−x)² for exmex (and Excel):
        // refused rather than read either way.
        match (minus, token) {
            (Some((at, _, true)), Token::Operator('^')) => {
                let (start, end) = (chars[at - 1].0, chars.get(i).map_or(text.len(), |&(e, _)| e));
                let base = text[start..end].trim_end();
                return Err(fail(
                    at,
                    format!("'{base}^…' is ambiguous: write -({}^…) or ({base})^…", base[1..].trim_start()),
                ));
            }
            (Some((_, _, true)), _) => minus = None,
            (None, Token::Operator('-')) if !after_operand => minus = Some((position, open.len(), false)),
            _ => {}
        }
        let after =
            |p: Option<Token>| p.map_or("at the start".to_string(), |t| format!("after {}", t.describe()));
        let expected_value =
            || fail(position, format!("expected a value {}, found {}", after(previous), token.describe()));
        match (after_operand, token) {
            (false, Token::Value(_)) => after_operand = true,
            (false, Token::Function(..)) => {}
            (false, Token::Operator('+' | '-')) => {}
            (false, Token::Open) => {
                let called = match previous {
                    Some(Token::Function(f, 2)) => Some(f),
                    _ => None,
                };
                open.push((position, called, 0));
            }
            (false, _) => return Err(expected_value()),
            (true, Token::Operator(_)) => after_operand = false,
            (true, Token::Close) => {
                let Some((_, called, commas)) = open.pop() else {
                    return Err(fail(position, "')' closes no '('".into()));
                };
                if let (Some(f), 0) = (called, commas) {
                    return Err(fail(position, format!("{f} takes 2 arguments, found 1")));
                }
            }
            (true, Token::Comma) => match open.last_mut() {
                Some((_, Some(_), commas @ 0)) => {
                    *commas = 1;
                    after_operand = false;
                }
                Some((_, Some(f), _)) => {
                    return Err(fail(position, format!("{f} takes 2 arguments, found more")))
                }
                _ => return Err(fail(position, "',' outside the arguments of atan2, min or max".into())),
            },
            (true, _) => {
                let before = previous.map(Token::describe).unwrap_or_default();
                return Err(fail(
                    position,
                    format!("missing operator between {before} and {}", token.describe()),
                ));
            }
        }
        if matches!(token, Token::Function(f, 2) if !rest[f.len()..].trim_start().starts_with('(')) {
            return Err(fail(
                position,
                format!("{} needs its two arguments in parentheses", token.describe()),
            ));
        }
        // The minus's operand is complete once a value stands at its level.
        if let Some((_, depth, done)) = &mut minus {
            *done = after_operand && open.len() == *depth;
        }
        previous = Some(token);
        i += len;
    }
    let end = chars.len() + 1;
    if !after_operand {
        let problem = match previous {
            None => "the expression is empty".into(),
            Some(p) => format!("expected a value after {}, found the end", p.describe()),
        };
        return Err(fail(end, problem));
    }
    match open.last() {
        Some(&(position, ..)) => Err(fail(position, "this '(' is never closed".into())),
        None => Ok(()),
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
    fn expressions_in_time_take_t_and_others_refuse_it() {
        let e = Expression::parse_in_time("t*z - x").unwrap();
        assert_eq!(e.at_time([1.0, 7.0, 4.0], 0.5).unwrap(), 1.0);
        let err = Expression::parse("x*t").unwrap_err().to_string();
        assert_eq!(err, "the expression 'x*t' uses 't'; only x, y and z are known");
        let err = Expression::parse_in_time("x*s").unwrap_err().to_string();
        assert_eq!(err, "the expression 'x*s' uses 's'; only x, y, z and t are known");
        let err = Expression::parse_in_time("1/t").unwrap().at_time([1.0, 2.0, 3.0], 0.0).unwrap_err();
        assert_eq!(err.to_string(), "the expression '1/t' is inf at (1, 2, 3), t = 0");
    }

    #[test]
    fn bad_expressions_are_named() {
        assert!(matches!(Expression::parse("sin(x"), Err(ExpressionError::Parse { position: 4, .. })));
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
    fn scientific_notation_is_read_and_out_of_range_numbers_are_named() {
        let at = |text: &str| Expression::parse(text).unwrap().at([2.0, 3.0, 5.0]).unwrap();
        assert_eq!(at("1e-3*x"), 1e-3 * 2.0);
        assert_eq!(at("2.5e3"), 2500.0);
        assert_eq!(at("1E+2 - z"), 95.0);
        assert_eq!(at(".5e1*y"), 15.0);
        assert_eq!(at("2*e"), 2.0 * std::f64::consts::E);
        assert_eq!(at("1e-310"), 1e-310);
        assert_eq!(
            Expression::parse("1e999*x").unwrap_err().to_string(),
            "the expression '1e999*x' holds the number 1e999, beyond double precision (magnitude at most 1.8e308)"
        );
        assert_eq!(
            Expression::parse("x + 2.5e-400").unwrap_err().to_string(),
            "the expression 'x + 2.5e-400' holds the number 2.5e-400, below the smallest double precision \
             number (4.9e-324): it would be 0"
        );
        assert_eq!(at("0e-999 + x"), 2.0);
    }

    #[test]
    fn mistakes_are_named_at_their_character_in_our_words() {
        let err = |text: &str| Expression::parse(text).unwrap_err().to_string();
        assert_eq!(
            err("foo(x)"),
            format!(
                "the expression 'foo(x)' calls 'foo', which is not a known function; the functions are {}",
                function_list()
            )
        );
        assert!(err("foo (x)").contains("abs, signum, sin, cos, tan, asin"), "{}", err("foo (x)"));
        let at = |text: &str, position: usize, problem: &str| {
            assert_eq!(
                err(text),
                format!("the expression '{text}' does not parse at character {position}: {problem}")
            );
        };
        at("sin(x", 4, "this '(' is never closed");
        at("x)", 2, "')' closes no '('");
        at("x y", 3, "missing operator between 'x' and 'y'");
        at("2x", 2, "missing operator between '2' and 'x'");
        at("abs(x)(y)", 7, "missing operator between ')' and '('");
        at("*x", 1, "expected a value at the start, found '*'");
        at("x**2", 3, "expected a value after '*', found '*'");
        at("x+", 3, "expected a value after '+', found the end");
        at("()", 2, "expected a value after '(', found ')'");
        at("", 1, "the expression is empty");
        at("x % 2", 3, "'%' is not part of an expression");
        at("{x}", 1, "'{' is not part of an expression");
        at("min(x)", 6, "min takes 2 arguments, found 1");
        at("min(x,y,z)", 8, "min takes 2 arguments, found more");
        at("x,y", 2, "',' outside the arguments of atan2, min or max");
        at("max x", 1, "'max' needs its two arguments in parentheses");
        at("1.2.3", 4, "missing operator between '1.2' and '.3'");
        at("-x^2", 1, "'-x^…' is ambiguous: write -(x^…) or (-x)^…");
        at("1 + -sin(y)^2", 5, "'-sin(y)^…' is ambiguous: write -(sin(y)^…) or (-sin(y))^…");
        at("y*(- 2^x)", 4, "'- 2^…' is ambiguous: write -(2^…) or (- 2)^…");
        for good in [
            "min(x, y)",
            "atan2(y,x)",
            "sin x",
            "-(x^2)",
            "(-x)^2",
            "x^-2",
            "-x*y^2",
            "2^-x",
            "--x",
            "log2(x)",
            "x\t+ y",
            "max(min(x,y),z)",
        ] {
            assert!(Expression::parse(good).is_ok(), "{good}");
        }
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

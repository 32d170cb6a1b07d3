//! RS-274/NGC expressions: numbers, parameters (`#12`, `##1`, `#<name>`), bracketed
//! expressions with `**`, `*`, `/`, `MOD`, `+`, `-`, the comparisons and the logical
//! operators, and the language's functions (`ABS`, `ACOS`, `ASIN`, `ATAN[y]/[x]`, `COS`,
//! `EXP`, `FIX`, `FUP`, `LN`, `ROUND`, `SIN`, `SQRT`, `TAN`, `EXISTS`). Angles in degrees.
//!
//! Parsed from a line already lower-cased with its spaces and comments removed
//! (`crate::lex`), as LinuxCNC reads it.

use crate::lex::Cursor;
use crate::{GcodeError, Params};

/// A unary function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Func {
    Abs,
    Acos,
    Asin,
    Cos,
    Exp,
    Fix,
    Fup,
    Ln,
    Round,
    Sin,
    Sqrt,
    Tan,
}

/// A binary operator, by precedence level (higher binds tighter).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Op {
    Pow,
    Mul,
    Div,
    Mod,
    Add,
    Sub,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
}

impl Op {
    fn level(self) -> u8 {
        match self {
            Op::Pow => 4,
            Op::Mul | Op::Div | Op::Mod => 3,
            Op::Add | Op::Sub => 2,
            Op::Eq | Op::Ne | Op::Gt | Op::Ge | Op::Lt | Op::Le => 1,
            Op::And | Op::Or | Op::Xor => 0,
        }
    }
}

/// An expression.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Expr {
    Num(f64),
    /// `#n`: the numbered parameter whose number the expression gives.
    Param(Box<Expr>),
    /// `#<name>` (lower case, spaces removed).
    Named(String),
    /// `EXISTS[#<name>]`.
    Exists(String),
    Neg(Box<Expr>),
    Call(Func, Box<Expr>),
    /// `ATAN[y]/[x]`.
    Atan(Box<Expr>, Box<Expr>),
    Binary(Op, Box<Expr>, Box<Expr>),
}

/// Deepest nesting of brackets and unary operators a value may have: a bound on the parser's
/// recursion, so that `[[[[…` cannot exhaust the stack.
const MAX_DEPTH: u32 = 64;

/// Parses a real value at the cursor: a number, a parameter, a bracketed expression, a
/// function call, or one of these after `+` or `-`.
pub(crate) fn real_value(c: &mut Cursor<'_>) -> Result<Expr, GcodeError> {
    value(c, 0)
}

fn value(c: &mut Cursor<'_>, depth: u32) -> Result<Expr, GcodeError> {
    if depth > MAX_DEPTH {
        return Err(c.error("expression nested too deeply"));
    }
    match c.peek() {
        Some(b'[') => {
            c.bump();
            let e = expression(c, depth + 1)?;
            c.expect(b']')?;
            Ok(e)
        }
        Some(b'#') => {
            c.bump();
            if c.peek() == Some(b'<') {
                Ok(Expr::Named(c.name()?))
            } else {
                Ok(Expr::Param(Box::new(value(c, depth + 1)?)))
            }
        }
        Some(b'-') => {
            c.bump();
            Ok(Expr::Neg(Box::new(value(c, depth + 1)?)))
        }
        Some(b'+') => {
            c.bump();
            value(c, depth + 1)
        }
        Some(b'0'..=b'9' | b'.') => Ok(Expr::Num(c.number()?)),
        Some(b'a'..=b'z') => function(c, depth),
        Some(other) => Err(c.error(&format!("unexpected '{}' in a value", other as char))),
        None => Err(c.error("a value is missing at the end of the line")),
    }
}

fn function(c: &mut Cursor<'_>, depth: u32) -> Result<Expr, GcodeError> {
    const NAMES: [(&str, Option<Func>); 14] = [
        ("abs", Some(Func::Abs)),
        ("acos", Some(Func::Acos)),
        ("asin", Some(Func::Asin)),
        ("atan", None),
        ("cos", Some(Func::Cos)),
        ("exists", None),
        ("exp", Some(Func::Exp)),
        ("fix", Some(Func::Fix)),
        ("fup", Some(Func::Fup)),
        ("ln", Some(Func::Ln)),
        ("round", Some(Func::Round)),
        ("sin", Some(Func::Sin)),
        ("sqrt", Some(Func::Sqrt)),
        ("tan", Some(Func::Tan)),
    ];
    let Some((name, func)) = NAMES.iter().find(|(n, _)| c.starts_with(n)) else {
        return Err(c.error("unknown function"));
    };
    c.advance(name.len());
    if *name == "exists" {
        c.expect(b'[')?;
        c.expect(b'#')?;
        let n = c.name()?;
        c.expect(b']')?;
        return Ok(Expr::Exists(n));
    }
    c.expect(b'[')?;
    let arg = expression(c, depth + 1)?;
    c.expect(b']')?;
    match func {
        Some(f) => Ok(Expr::Call(*f, Box::new(arg))),
        None => {
            c.expect(b'/')?;
            c.expect(b'[')?;
            let x = expression(c, depth + 1)?;
            c.expect(b']')?;
            Ok(Expr::Atan(Box::new(arg), Box::new(x)))
        }
    }
}

/// The binary operator at the cursor, if any (not consumed).
fn operator(c: &Cursor<'_>) -> Option<(Op, usize)> {
    const OPS: [(&str, Op); 15] = [
        ("**", Op::Pow),
        ("*", Op::Mul),
        ("/", Op::Div),
        ("mod", Op::Mod),
        ("+", Op::Add),
        ("-", Op::Sub),
        ("eq", Op::Eq),
        ("ne", Op::Ne),
        ("gt", Op::Gt),
        ("ge", Op::Ge),
        ("lt", Op::Lt),
        ("le", Op::Le),
        ("and", Op::And),
        ("or", Op::Or),
        ("xor", Op::Xor),
    ];
    OPS.iter()
        .find(|(s, _)| c.starts_with(s))
        .map(|(s, op)| (*op, s.len()))
}

/// An expression inside brackets, up to (not including) the closing bracket: operators
/// left-associative by precedence (`**` too, as LinuxCNC evaluates it).
fn expression(c: &mut Cursor<'_>, depth: u32) -> Result<Expr, GcodeError> {
    let mut operands = vec![value(c, depth)?];
    let mut operators: Vec<Op> = Vec::new();
    while let Some((op, len)) = operator(c) {
        c.advance(len);
        while let Some(top) = operators.last().copied() {
            if top.level() < op.level() {
                break;
            }
            reduce(&mut operands, &mut operators);
        }
        operators.push(op);
        operands.push(value(c, depth)?);
    }
    while !operators.is_empty() {
        reduce(&mut operands, &mut operators);
    }
    Ok(operands.pop().unwrap_or(Expr::Num(0.0)))
}

fn reduce(operands: &mut Vec<Expr>, operators: &mut Vec<Op>) {
    if let (Some(op), Some(b), Some(a)) = (operators.pop(), operands.pop(), operands.pop()) {
        operands.push(Expr::Binary(op, Box::new(a), Box::new(b)));
    }
}

/// Evaluates `e` against the parameters; `line` names the error's line.
pub(crate) fn eval(e: &Expr, params: &Params, line: u32) -> Result<f64, GcodeError> {
    let err = |message: &str| GcodeError::Eval {
        line,
        message: message.to_string(),
    };
    let v = match e {
        Expr::Num(v) => *v,
        Expr::Param(n) => {
            let n = eval(n, params, line)?;
            params.numbered(n).ok_or_else(|| {
                err(&format!(
                    "parameter #{n} is not a parameter number (1–5602)"
                ))
            })?
        }
        Expr::Named(name) => params
            .named(name)
            .ok_or_else(|| err(&format!("parameter #<{name}> is read before it is set")))?,
        Expr::Exists(name) => f64::from(u8::from(params.named(name).is_some())),
        Expr::Neg(a) => -eval(a, params, line)?,
        Expr::Call(f, a) => {
            let a = eval(a, params, line)?;
            match f {
                Func::Abs => a.abs(),
                Func::Acos | Func::Asin if !(-1.0..=1.0).contains(&a) => {
                    return Err(err(&format!("{f:?} of {a}, outside [-1, 1]")));
                }
                Func::Acos => a.acos().to_degrees(),
                Func::Asin => a.asin().to_degrees(),
                Func::Cos => a.to_radians().cos(),
                Func::Exp => a.exp(),
                Func::Fix => a.floor(),
                Func::Fup => a.ceil(),
                Func::Ln if a <= 0.0 => return Err(err(&format!("LN of {a}, not positive"))),
                Func::Ln => a.ln(),
                Func::Round => a.round(),
                Func::Sin => a.to_radians().sin(),
                Func::Sqrt if a < 0.0 => return Err(err(&format!("SQRT of {a}, negative"))),
                Func::Sqrt => a.sqrt(),
                Func::Tan => a.to_radians().tan(),
            }
        }
        Expr::Atan(y, x) => eval(y, params, line)?
            .atan2(eval(x, params, line)?)
            .to_degrees(),
        Expr::Binary(op, a, b) => {
            let (a, b) = (eval(a, params, line)?, eval(b, params, line)?);
            let truth = |t: bool| f64::from(u8::from(t));
            match op {
                Op::Pow => a.powf(b),
                Op::Mul => a * b,
                Op::Div if b == 0.0 => return Err(err("division by zero")),
                Op::Div => a / b,
                Op::Mod if b == 0.0 => return Err(err("MOD by zero")),
                // NGC's MOD takes the sign of the divisor's side: the result is in [0, |b|).
                Op::Mod => a.rem_euclid(b),
                Op::Add => a + b,
                Op::Sub => a - b,
                Op::Eq => truth(a == b),
                Op::Ne => truth(a != b),
                Op::Gt => truth(a > b),
                Op::Ge => truth(a >= b),
                Op::Lt => truth(a < b),
                Op::Le => truth(a <= b),
                Op::And => truth(a != 0.0 && b != 0.0),
                Op::Or => truth(a != 0.0 || b != 0.0),
                Op::Xor => truth((a != 0.0) != (b != 0.0)),
            }
        }
    };
    if v.is_finite() {
        Ok(v)
    } else {
        Err(err("the value is not a finite number"))
    }
}

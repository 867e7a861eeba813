//! The abstract syntax tree and its re-parseable printed form.

use std::fmt;

use crate::catalog::{Constant, Function};

/// A binary operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BinOp {
    /// `+` (scalars or vectors).
    Add,
    /// `-` (scalars or vectors).
    Sub,
    /// `*`: product of scalars, scalar·vector, or dot product of two vectors.
    Mul,
    /// `/`: scalar division, or vector divided by a scalar.
    Div,
    /// `%`: cross product of two vectors.
    Cross,
    /// `**`: power (scalars), right-associative.
    Pow,
}

impl BinOp {
    /// The operator as written.
    pub fn symbol(self) -> &'static str {
        match self {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Cross => "%",
            BinOp::Pow => "**",
        }
    }
}

/// A parsed function expression.
///
/// Trees produced by [`crate::parse`] are well typed (vectors only where allowed, correct
/// argument counts) and never contain negative [`Expr::Number`] literals (a leading minus is an
/// [`Expr::Neg`] node). Hand-built trees are accepted by the evaluator, which reports
/// inconsistencies as [`crate::EvalError`]s instead of panicking.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    /// A numeric literal.
    Number(f64),
    /// A literal with the `D` (degrees) suffix; holds the value as written, in degrees.
    /// It evaluates to `value · π/180`.
    Degrees(f64),
    /// A named constant or system value (`PI`, `DTOR`, `RTOD`, `TIME`, `MODE`).
    Constant(Constant),
    /// Unary minus.
    Neg(Box<Expr>),
    /// A binary operation.
    Binary {
        /// The operator.
        op: BinOp,
        /// Left operand.
        lhs: Box<Expr>,
        /// Right operand.
        rhs: Box<Expr>,
    },
    /// A vector literal `[x, y, z]`.
    Vector(Box<[Expr; 3]>),
    /// Arithmetic `IF(test: lt, eq, gt)`.
    If {
        /// The tested value.
        test: Box<Expr>,
        /// Result when `test < 0`.
        lt: Box<Expr>,
        /// Result when `test = 0`.
        eq: Box<Expr>,
        /// Result when `test > 0`.
        gt: Box<Expr>,
    },
    /// A call of a known function.
    Call {
        /// The function.
        func: Function,
        /// Its arguments, in order.
        args: Vec<Expr>,
    },
    /// `USER(r1, ..., rn)`: a user subroutine not linked to any code. It cannot be
    /// evaluated; callers should refuse the element (see [`Expr::contains_user`]) or link it
    /// ([`Expr::link_user`]).
    User(Vec<Expr>),
    /// `USER(r1, ..., rn)` linked to the subroutine that computes it.
    Linked {
        /// The subroutine.
        routine: crate::user::Routine,
        /// The parameters r1 … rn.
        args: Vec<Expr>,
    },
}

impl Expr {
    /// Calls `visit` on this node and every node below it (pre-order).
    pub fn walk<'a>(&'a self, visit: &mut dyn FnMut(&'a Expr)) {
        visit(self);
        match self {
            Expr::Number(_) | Expr::Degrees(_) | Expr::Constant(_) => {}
            Expr::Neg(e) => e.walk(visit),
            Expr::Binary { lhs, rhs, .. } => {
                lhs.walk(visit);
                rhs.walk(visit);
            }
            Expr::Vector(items) => items.iter().for_each(|e| e.walk(visit)),
            Expr::If { test, lt, eq, gt } => {
                test.walk(visit);
                lt.walk(visit);
                eq.walk(visit);
                gt.walk(visit);
            }
            Expr::Call { args, .. } | Expr::User(args) | Expr::Linked { args, .. } => {
                args.iter().for_each(|e| e.walk(visit))
            }
        }
    }

    /// True if any node satisfies `pred`.
    pub fn any(&self, pred: &mut dyn FnMut(&Expr) -> bool) -> bool {
        let mut found = false;
        self.walk(&mut |e| {
            if !found && pred(e) {
                found = true;
            }
        });
        found
    }

    /// True if the expression calls `USER(...)` anywhere without a linked subroutine. Such an
    /// expression cannot be evaluated; the caller should report "user subroutine cannot be
    /// run" for the element.
    pub fn contains_user(&self) -> bool {
        self.any(&mut |e| matches!(e, Expr::User(_)))
    }

    /// True if the expression calls a linked subroutine anywhere.
    pub fn contains_linked(&self) -> bool {
        self.any(&mut |e| matches!(e, Expr::Linked { .. }))
    }

    /// The expression with every unlinked `USER(…)` call linked to the routine `link`
    /// returns for it (`None`: left unlinked).
    pub fn link_user(self, link: &mut dyn FnMut(&[Expr]) -> Option<crate::user::Routine>) -> Expr {
        let mut go = |e: Box<Expr>| Box::new(e.link_user(link));
        match self {
            Expr::User(args) => match link(&args) {
                Some(routine) => Expr::Linked { routine, args },
                None => Expr::User(args),
            },
            Expr::Neg(x) => Expr::Neg(go(x)),
            Expr::Binary { op, lhs, rhs } => {
                let lhs = go(lhs);
                Expr::Binary {
                    op,
                    lhs,
                    rhs: go(rhs),
                }
            }
            Expr::Vector(items) => {
                let [a, b, c] = *items;
                Expr::Vector(Box::new([
                    a.link_user(link),
                    b.link_user(link),
                    c.link_user(link),
                ]))
            }
            Expr::If { test, lt, eq, gt } => {
                let (test, lt) = (go(test), go(lt));
                let (eq, gt) = (go(eq), go(gt));
                Expr::If { test, lt, eq, gt }
            }
            Expr::Call { func, args } => Expr::Call {
                func,
                args: args.into_iter().map(|a| a.link_user(link)).collect(),
            },
            e @ (Expr::Number(_) | Expr::Degrees(_) | Expr::Constant(_) | Expr::Linked { .. }) => e,
        }
    }

    /// True if the expression uses `TIME`.
    pub fn uses_time(&self) -> bool {
        self.any(&mut |e| matches!(e, Expr::Constant(Constant::Time)))
    }

    /// True if the expression uses a measure (including `ORIENT`), an element force or a state
    /// reference, i.e. depends on the model state (and is therefore not allowed in a MOTION
    /// function).
    pub fn uses_state(&self) -> bool {
        self.any(&mut |e| {
            matches!(
                e,
                Expr::Call {
                    func: Function::Measure(_)
                        | Function::ElementForce(_)
                        | Function::State(_)
                        | Function::Orient,
                    ..
                }
            )
        })
    }
}

// Printing precedence levels (higher binds tighter).
const PREC_ADD: u8 = 1;
const PREC_MUL: u8 = 2;
const PREC_UNARY: u8 = 3;
const PREC_POW: u8 = 4;
const PREC_ATOM: u8 = 5;

fn precedence(e: &Expr) -> u8 {
    match e {
        Expr::Number(v) if *v < 0.0 || v.is_sign_negative() => PREC_UNARY,
        Expr::Neg(_) => PREC_UNARY,
        Expr::Binary { op, .. } => match op {
            BinOp::Add | BinOp::Sub => PREC_ADD,
            BinOp::Mul | BinOp::Div | BinOp::Cross => PREC_MUL,
            BinOp::Pow => PREC_POW,
        },
        _ => PREC_ATOM,
    }
}

/// Writes `e`, parenthesised if its precedence is below `min`.
fn write_at(f: &mut fmt::Formatter<'_>, e: &Expr, min: u8) -> fmt::Result {
    if precedence(e) < min {
        write!(f, "({e})")
    } else {
        write!(f, "{e}")
    }
}

fn write_list(f: &mut fmt::Formatter<'_>, args: &[Expr]) -> fmt::Result {
    for (i, a) in args.iter().enumerate() {
        if i > 0 {
            f.write_str(", ")?;
        }
        write!(f, "{a}")?;
    }
    Ok(())
}

/// Prints the expression as re-parseable text with the minimum of parentheses:
/// `parse(&e.to_string()) == Ok(e)` for every tree produced by [`crate::parse`].
/// Numbers use Rust's shortest round-trip representation; names are upper case.
impl fmt::Display for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Expr::Number(v) => write!(f, "{v}"),
            Expr::Degrees(v) => write!(f, "{v}D"),
            Expr::Constant(c) => f.write_str(c.name()),
            Expr::Neg(e) => {
                f.write_str("-")?;
                write_at(f, e, PREC_UNARY)
            }
            Expr::Binary { op, lhs, rhs } => {
                let (lmin, rmin) = match op {
                    BinOp::Add | BinOp::Sub => (PREC_ADD, PREC_MUL),
                    BinOp::Mul | BinOp::Div | BinOp::Cross => (PREC_MUL, PREC_UNARY),
                    BinOp::Pow => (PREC_ATOM, PREC_UNARY),
                };
                write_at(f, lhs, lmin)?;
                match op {
                    BinOp::Add | BinOp::Sub => write!(f, " {} ", op.symbol())?,
                    _ => f.write_str(op.symbol())?,
                }
                write_at(f, rhs, rmin)
            }
            Expr::Vector(items) => {
                f.write_str("[")?;
                write_list(f, items.as_slice())?;
                f.write_str("]")
            }
            Expr::If { test, lt, eq, gt } => write!(f, "IF({test}: {lt}, {eq}, {gt})"),
            Expr::Call { func, args } => {
                write!(f, "{}(", func.name())?;
                write_list(f, args)?;
                f.write_str(")")
            }
            Expr::User(args) | Expr::Linked { args, .. } => {
                f.write_str("USER(")?;
                write_list(f, args)?;
                f.write_str(")")
            }
        }
    }
}

//! Error types: [`ParseError`] (syntax, with a byte offset) and [`EvalError`] (evaluation).

use thiserror::Error;

/// A syntax error in a function expression.
///
/// `offset` is the **byte offset** into the text given to [`crate::parse`] at which the problem
/// was detected (the caller maps it to line:column of the dataset). `message` is a complete
/// sentence fragment without location, e.g. `expected ')' to close '(' opened at offset 12,
/// found end of expression`.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{message} (at byte offset {offset})")]
pub struct ParseError {
    /// Byte offset into the parsed text (may equal the text length for "unexpected end").
    pub offset: usize,
    /// Human-readable description of the problem.
    pub message: String,
}

impl ParseError {
    pub(crate) fn new(offset: usize, message: impl Into<String>) -> Self {
        ParseError {
            offset,
            message: message.into(),
        }
    }
}

/// Broad category of an [`EvalError`], so that callers can react differently (for example
/// refuse a model containing `USER(...)` up front, or report a domain error with the time).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EvalErrorKind {
    /// A mathematical domain error: division by zero, `SQRT` of a negative number, `LOG` of a
    /// non-positive number, `ACOS`/`ASIN` out of range, overflow, non-finite derivative, ...
    Domain,
    /// An argument has an invalid value (an id that is not a non-negative integer, `JOINT`
    /// component outside 1..8, `IMPACT` with `d <= 0`, spline derivative order outside 0..2, ...).
    InvalidArgument,
    /// The environment does not know a referenced id (VARIABLE, ARRAY, DIFF, SPLINE, marker,
    /// element, ...).
    UnknownReference,
    /// A quantity is not available in this evaluation context (for example a measure in a
    /// context whose environment does not provide measures).
    Unavailable,
    /// [`crate::evaluate_time_series`] (or [`crate::evaluate_path_series`] in an environment
    /// that has no series of that quantity) met a measure or state reference: a MOTION
    /// function must depend on time only.
    NotTimeOnly,
    /// The expression calls `USER(...)`, a user subroutine, which cannot be run.
    UserSubroutine,
}

/// An error raised while evaluating an expression.
///
/// The message names the offending function or operator (e.g. `SQRT of negative number -4`);
/// the caller is expected to prefix it with the element name and the simulation time.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{message}")]
pub struct EvalError {
    /// Category of the error.
    pub kind: EvalErrorKind,
    /// Human-readable description.
    pub message: String,
}

impl EvalError {
    /// Creates an error of the given kind.
    pub fn new(kind: EvalErrorKind, message: impl Into<String>) -> Self {
        EvalError {
            kind,
            message: message.into(),
        }
    }

    /// A mathematical domain error ([`EvalErrorKind::Domain`]).
    pub fn domain(message: impl Into<String>) -> Self {
        Self::new(EvalErrorKind::Domain, message)
    }

    /// An invalid argument value ([`EvalErrorKind::InvalidArgument`]).
    pub fn invalid_argument(message: impl Into<String>) -> Self {
        Self::new(EvalErrorKind::InvalidArgument, message)
    }

    /// An id unknown to the environment ([`EvalErrorKind::UnknownReference`]); environments
    /// should use this for a missing VARIABLE, ARRAY, DIFF, marker or element.
    pub fn unknown_reference(message: impl Into<String>) -> Self {
        Self::new(EvalErrorKind::UnknownReference, message)
    }

    /// A quantity the environment cannot provide ([`EvalErrorKind::Unavailable`]).
    pub fn unavailable(message: impl Into<String>) -> Self {
        Self::new(EvalErrorKind::Unavailable, message)
    }

    /// `what` (e.g. `DX`) met where only TIME may vary ([`EvalErrorKind::NotTimeOnly`]): the
    /// error of a MOTION function that uses the model state.
    pub fn not_time_only(what: &str) -> Self {
        Self::new(
            EvalErrorKind::NotTimeOnly,
            format!(
                "a MOTION function must depend on time only, but this expression uses {what}, \
                 which depends on the model state"
            ),
        )
    }
}

//! [`Dual`]: a value with a sparse gradient (forward-mode automatic differentiation).
//!
//! Gradients live in vectors that are recycled: a dropped [`Dual`] returns its vector to a
//! per-thread pool and new ones take theirs from it, so that once an evaluation has run, the
//! same evaluation again (the integrator's force Jacobians at every matrix refresh) takes no
//! memory from the allocator.

use std::cell::RefCell;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A value together with its partial derivatives with respect to environment-defined
/// variables.
///
/// The gradient is sparse: a list of `(variable index, ∂value/∂variable)` pairs, sorted by
/// index with no duplicates. Variables absent from the list have derivative zero. What the
/// indices mean is up to the [`crate::Env`] implementation (for example the 6 position and 6
/// velocity coordinates of every part).
#[derive(Debug, PartialEq, Default)]
pub struct Dual {
    value: f64,
    grad: Vec<(u32, f64)>,
}

/// Capacity of a fresh gradient vector: the 24 coordinates (6 position and 6 velocity of
/// each part) a two-body force element depends on fit without growing.
const FRESH_CAPACITY: usize = 24;

/// Most gradient vectors a thread keeps for reuse; more are freed.
const POOL_LIMIT: usize = 1024;

thread_local! {
    /// Empty gradient vectors left by dropped [`Dual`]s.
    static POOL: RefCell<Vec<Vec<(u32, f64)>>> = const { RefCell::new(Vec::new()) };
}

/// An empty gradient vector with room for at least `capacity` entries, recycled if possible.
fn gradient_vec(capacity: usize) -> Vec<(u32, f64)> {
    let recycled = POOL
        .try_with(|p| p.try_borrow_mut().ok().and_then(|mut p| p.pop()))
        .ok()
        .flatten();
    match recycled {
        Some(mut v) => {
            v.reserve(capacity);
            v
        }
        None => Vec::with_capacity(capacity.max(FRESH_CAPACITY)),
    }
}

impl Drop for Dual {
    fn drop(&mut self) {
        if self.grad.capacity() == 0 {
            return;
        }
        let mut v = std::mem::take(&mut self.grad);
        v.clear();
        // A full pool, a busy one or a thread shutting down frees the vector instead.
        let _ = POOL.try_with(|p| {
            if let Ok(mut p) = p.try_borrow_mut() {
                if p.len() < POOL_LIMIT {
                    p.push(v);
                }
            }
        });
    }
}

impl Clone for Dual {
    fn clone(&self) -> Self {
        Dual {
            value: self.value,
            grad: copy_of(&self.grad),
        }
    }
}

/// A (recycled) copy of a gradient; an empty one stays unallocated.
fn copy_of(g: &[(u32, f64)]) -> Vec<(u32, f64)> {
    if g.is_empty() {
        return Vec::new();
    }
    let mut v = gradient_vec(g.len());
    v.extend_from_slice(g);
    v
}

/// `c · d`, treating a zero factor as exact (so that `0 · ∞ = 0`).
#[inline]
fn mul0(c: f64, d: f64) -> f64 {
    if c == 0.0 || d == 0.0 {
        0.0
    } else {
        c * d
    }
}

/// Sparse linear combination `a·x + b·y` of two sorted gradients.
fn lincomb(a: f64, x: &[(u32, f64)], b: f64, y: &[(u32, f64)]) -> Vec<(u32, f64)> {
    if x.is_empty() && y.is_empty() {
        return Vec::new();
    }
    let mut out = gradient_vec(x.len() + y.len());
    let (mut xi, mut yi) = (x.iter().peekable(), y.iter().peekable());
    loop {
        match (xi.peek(), yi.peek()) {
            (Some(&&(i, dx)), Some(&&(j, dy))) => {
                if i < j {
                    out.push((i, mul0(a, dx)));
                    xi.next();
                } else if j < i {
                    out.push((j, mul0(b, dy)));
                    yi.next();
                } else {
                    out.push((i, mul0(a, dx) + mul0(b, dy)));
                    xi.next();
                    yi.next();
                }
            }
            (Some(&&(i, dx)), None) => {
                out.push((i, mul0(a, dx)));
                xi.next();
            }
            (None, Some(&&(j, dy))) => {
                out.push((j, mul0(b, dy)));
                yi.next();
            }
            (None, None) => return out,
        }
    }
}

/// `c · x` of a sorted gradient.
fn scaled(c: f64, x: &[(u32, f64)]) -> Vec<(u32, f64)> {
    if x.is_empty() {
        return Vec::new();
    }
    let mut out = gradient_vec(x.len());
    out.extend(x.iter().map(|&(i, d)| (i, mul0(c, d))));
    out
}

impl Dual {
    /// A constant (empty gradient).
    pub fn constant(value: f64) -> Self {
        Dual {
            value,
            grad: Vec::new(),
        }
    }

    /// The variable number `index` itself, at `value` (gradient `[(index, 1)]`).
    pub fn variable(value: f64, index: u32) -> Self {
        let mut grad = gradient_vec(1);
        grad.push((index, 1.0));
        Dual { value, grad }
    }

    /// A value with the given partial derivatives. The entries may come in any order;
    /// duplicates are summed.
    pub fn new(value: f64, gradient: impl IntoIterator<Item = (u32, f64)>) -> Self {
        let mut grad = gradient_vec(0);
        grad.extend(gradient);
        grad.sort_by_key(|&(i, _)| i);
        grad.dedup_by(|later, earlier| {
            if later.0 == earlier.0 {
                earlier.1 += later.1;
                true
            } else {
                false
            }
        });
        Dual { value, grad }
    }

    /// The value.
    pub fn value(&self) -> f64 {
        self.value
    }

    /// The sparse gradient, sorted by variable index.
    pub fn gradient(&self) -> &[(u32, f64)] {
        &self.grad
    }

    /// Consumes `self`, returning the gradient.
    pub fn into_gradient(mut self) -> Vec<(u32, f64)> {
        std::mem::take(&mut self.grad)
    }

    /// ∂value/∂(variable `index`) (zero if absent).
    pub fn derivative(&self, index: u32) -> f64 {
        self.grad
            .binary_search_by_key(&index, |&(i, _)| i)
            .ok()
            .and_then(|k| self.grad.get(k))
            .map_or(0.0, |&(_, d)| d)
    }

    /// True if every partial derivative is zero.
    pub fn is_constant(&self) -> bool {
        self.grad.iter().all(|&(_, d)| d == 0.0)
    }

    /// Chain rule: `g(self)` for a scalar function `g` with `g(value) = g0`, `g'(value) = g1`.
    pub fn map(&self, g0: f64, g1: f64) -> Dual {
        Dual {
            value: g0,
            grad: scaled(g1, &self.grad),
        }
    }

    /// `self · c` for a constant `c`.
    pub fn scale(&self, c: f64) -> Dual {
        self.map(self.value * c, c)
    }

    /// Square root (chain rule; the derivative is infinite at 0).
    pub fn sqrt(&self) -> Dual {
        let s = self.value.sqrt();
        self.map(s, 0.5 / s)
    }

    /// Sine.
    pub fn sin(&self) -> Dual {
        self.map(self.value.sin(), self.value.cos())
    }

    /// Cosine.
    pub fn cos(&self) -> Dual {
        self.map(self.value.cos(), -self.value.sin())
    }

    /// Exponential.
    pub fn exp(&self) -> Dual {
        let e = self.value.exp();
        self.map(e, e)
    }

    pub(crate) fn with_value(mut self, value: f64) -> Dual {
        self.value = value;
        self
    }

    pub(crate) fn add_ref(&self, o: &Dual) -> Dual {
        let grad = if o.grad.is_empty() {
            copy_of(&self.grad)
        } else if self.grad.is_empty() {
            copy_of(&o.grad)
        } else {
            lincomb(1.0, &self.grad, 1.0, &o.grad)
        };
        Dual {
            value: self.value + o.value,
            grad,
        }
    }

    pub(crate) fn sub_ref(&self, o: &Dual) -> Dual {
        let grad = if o.grad.is_empty() {
            copy_of(&self.grad)
        } else {
            lincomb(1.0, &self.grad, -1.0, &o.grad)
        };
        Dual {
            value: self.value - o.value,
            grad,
        }
    }

    pub(crate) fn mul_ref(&self, o: &Dual) -> Dual {
        Dual {
            value: self.value * o.value,
            grad: lincomb(o.value, &self.grad, self.value, &o.grad),
        }
    }

    pub(crate) fn div_ref(&self, o: &Dual) -> Dual {
        let q = self.value / o.value;
        Dual {
            value: q,
            grad: lincomb(1.0 / o.value, &self.grad, -q / o.value, &o.grad),
        }
    }

    pub(crate) fn neg_ref(&self) -> Dual {
        Dual {
            value: -self.value,
            grad: scaled(-1.0, &self.grad),
        }
    }
}

macro_rules! dual_binop {
    ($trait:ident, $method:ident, $imp:ident) => {
        impl $trait<&Dual> for &Dual {
            type Output = Dual;
            fn $method(self, o: &Dual) -> Dual {
                self.$imp(o)
            }
        }
        impl $trait<Dual> for Dual {
            type Output = Dual;
            fn $method(self, o: Dual) -> Dual {
                self.$imp(&o)
            }
        }
        impl $trait<&Dual> for Dual {
            type Output = Dual;
            fn $method(self, o: &Dual) -> Dual {
                self.$imp(o)
            }
        }
        impl $trait<Dual> for &Dual {
            type Output = Dual;
            fn $method(self, o: Dual) -> Dual {
                self.$imp(&o)
            }
        }
        impl $trait<f64> for Dual {
            type Output = Dual;
            fn $method(self, o: f64) -> Dual {
                self.$imp(&Dual::constant(o))
            }
        }
        impl $trait<f64> for &Dual {
            type Output = Dual;
            fn $method(self, o: f64) -> Dual {
                self.$imp(&Dual::constant(o))
            }
        }
    };
}

dual_binop!(Add, add, add_ref);
dual_binop!(Sub, sub, sub_ref);
dual_binop!(Mul, mul, mul_ref);
dual_binop!(Div, div, div_ref);

impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        self.neg_ref()
    }
}

impl Neg for &Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        self.neg_ref()
    }
}

impl From<f64> for Dual {
    fn from(value: f64) -> Self {
        Dual::constant(value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arithmetic() {
        let x = Dual::variable(2.0, 0);
        let y = Dual::variable(3.0, 5);
        let p = &x * &y;
        assert_eq!(p.value(), 6.0);
        assert_eq!(p.gradient(), &[(0, 3.0), (5, 2.0)]);
        let q = &x / &y;
        assert!((q.derivative(5) + 2.0 / 9.0).abs() < 1e-15);
        let s = (&x + &y) - x.clone() * 2.0;
        assert_eq!(s.gradient(), &[(0, -1.0), (5, 1.0)]);
        assert_eq!((-x).derivative(0), -1.0);
    }

    #[test]
    fn new_sorts_and_merges() {
        let d = Dual::new(1.0, [(3, 1.0), (1, 2.0), (3, 0.5)]);
        assert_eq!(d.gradient(), &[(1, 2.0), (3, 1.5)]);
        assert_eq!(d.derivative(2), 0.0);
        assert!(!d.is_constant());
        assert!(Dual::constant(4.0).is_constant());
    }

    #[test]
    fn recycled_gradients_start_empty() {
        let long = Dual::new(1.0, (0..40).map(|i| (i, 1.0)));
        let copy = long.clone();
        assert_eq!(copy.gradient().len(), 40);
        drop(long);
        drop(copy);
        // These take the vectors just dropped.
        let x = Dual::variable(2.0, 7);
        assert_eq!(x.gradient(), &[(7, 1.0)]);
        let y = x.scale(3.0) + Dual::variable(1.0, 2);
        assert_eq!(y.gradient(), &[(2, 1.0), (7, 3.0)]);
        assert_eq!(y.into_gradient(), vec![(2, 1.0), (7, 3.0)]);
        assert!(Dual::constant(1.0).gradient().is_empty());
    }

    #[test]
    fn zero_times_infinite_derivative_is_zero() {
        let x = Dual::new(0.0, [(0, 0.0)]);
        assert_eq!(x.sqrt().derivative(0), 0.0);
    }
}

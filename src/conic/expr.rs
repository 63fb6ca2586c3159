//! Affine scalar expressions `a·x + c` over the problem's variables.

use super::error::ConicError;
use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

/// A scalar decision variable of one [`Problem`](super::Problem): its index
/// in that problem's variable vector and the problem's identity. Copy it
/// freely; using it with another problem or its solution is an error
/// ([`ConicError::ForeignHandle`]), never an alias.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Var {
    pub(crate) problem: u32,
    pub(crate) index: u32,
}

impl Var {
    /// Index of this variable in the solver's primal vector `x`.
    pub fn index(self) -> usize {
        self.index as usize
    }
}

/// An affine scalar expression `Σ aᵢ xᵢ + c`.
///
/// Terms may repeat until [`AffExpr::compact`] merges them; every operation
/// is exact arithmetic on the coefficients, so evaluating an expression at
/// `x` equals doing the same arithmetic on the numbers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AffExpr {
    /// `(variable, coefficient)` pairs.
    pub(crate) terms: Vec<(Var, f64)>,
    /// The constant `c`.
    pub(crate) constant: f64,
}

impl AffExpr {
    /// The zero expression.
    pub fn zero() -> Self {
        Self::default()
    }

    /// A constant expression.
    pub fn constant(c: f64) -> Self {
        Self {
            terms: Vec::new(),
            constant: c,
        }
    }

    /// `coef · v`.
    pub fn term(v: Var, coef: f64) -> Self {
        Self {
            terms: vec![(v, coef)],
            constant: 0.0,
        }
    }

    /// `Σ coefs[i] · vars[i] + c`; the lengths must match.
    pub fn linear(vars: &[Var], coefs: &[f64], c: f64) -> Result<Self, ConicError> {
        if vars.len() != coefs.len() {
            return Err(ConicError::DimensionMismatch {
                what: "AffExpr::linear".into(),
                expected: format!("{} coefficients (one per variable)", vars.len()),
                found: format!("{}", coefs.len()),
            });
        }
        let mut e = Self::constant(c);
        for (v, &a) in vars.iter().zip(coefs) {
            e.add_term(*v, a);
        }
        Ok(e)
    }

    /// The constant part `c`.
    pub fn constant_term(&self) -> f64 {
        self.constant
    }

    /// The `(variable, coefficient)` pairs after merging repeats and dropping zeros.
    pub fn coefficients(&self) -> Vec<(Var, f64)> {
        let mut e = self.clone();
        e.compact();
        e.terms
    }

    /// Adds `coef · v` in place.
    pub fn add_term(&mut self, v: Var, coef: f64) {
        self.terms.push((v, coef));
    }

    /// Sorts terms by variable, merges repeats and drops exact zeros.
    pub fn compact(&mut self) {
        if self.terms.len() < 2 {
            self.terms.retain(|t| t.1 != 0.0);
            return;
        }
        self.terms.sort_by_key(|t| t.0);
        let mut out: Vec<(Var, f64)> = Vec::with_capacity(self.terms.len());
        for &(i, a) in &self.terms {
            match out.last_mut() {
                Some(last) if last.0 == i => last.1 += a,
                _ => out.push((i, a)),
            }
        }
        out.retain(|t| t.1 != 0.0);
        self.terms = out;
    }

    /// Value at the primal point `x` (indexed by [`Var::index`]).
    pub fn eval(&self, x: &[f64]) -> f64 {
        self.terms
            .iter()
            .map(|&(v, a)| a * x[v.index()])
            .sum::<f64>()
            + self.constant
    }

    /// Whether every coefficient and the constant are finite.
    pub fn is_finite(&self) -> bool {
        self.constant.is_finite() && self.terms.iter().all(|t| t.1.is_finite())
    }

    /// Its variables.
    pub(crate) fn vars(&self) -> impl Iterator<Item = Var> + '_ {
        self.terms.iter().map(|t| t.0)
    }

    /// `self · s` in place.
    pub fn scale(&mut self, s: f64) {
        self.constant *= s;
        for t in &mut self.terms {
            t.1 *= s;
        }
    }

    /// `self += s · other`.
    pub fn axpy(&mut self, s: f64, other: &AffExpr) {
        self.constant += s * other.constant;
        self.terms
            .extend(other.terms.iter().map(|&(i, a)| (i, s * a)));
    }

    /// Whether `self − other` is identically zero up to `tol` per coefficient.
    pub fn approx_eq(&self, other: &AffExpr, tol: f64) -> bool {
        let mut d = self.clone();
        d.axpy(-1.0, other);
        d.compact();
        d.constant.abs() <= tol && d.terms.iter().all(|t| t.1.abs() <= tol)
    }
}

impl From<Var> for AffExpr {
    fn from(v: Var) -> Self {
        AffExpr::term(v, 1.0)
    }
}
impl From<&Var> for AffExpr {
    fn from(v: &Var) -> Self {
        AffExpr::term(*v, 1.0)
    }
}
impl From<f64> for AffExpr {
    fn from(c: f64) -> Self {
        AffExpr::constant(c)
    }
}
impl From<&AffExpr> for AffExpr {
    fn from(e: &AffExpr) -> Self {
        e.clone()
    }
}

impl<T: Into<AffExpr>> AddAssign<T> for AffExpr {
    fn add_assign(&mut self, rhs: T) {
        let r = rhs.into();
        self.constant += r.constant;
        self.terms.extend(r.terms);
    }
}
impl<T: Into<AffExpr>> SubAssign<T> for AffExpr {
    fn sub_assign(&mut self, rhs: T) {
        self.axpy(-1.0, &rhs.into());
    }
}

macro_rules! affine_ops {
    ($($t:ty),*) => {$(
        impl<R: Into<AffExpr>> Add<R> for $t {
            type Output = AffExpr;
            fn add(self, rhs: R) -> AffExpr {
                let mut e: AffExpr = self.into();
                e += rhs;
                e
            }
        }
        impl<R: Into<AffExpr>> Sub<R> for $t {
            type Output = AffExpr;
            fn sub(self, rhs: R) -> AffExpr {
                let mut e: AffExpr = self.into();
                e -= rhs;
                e
            }
        }
        impl Mul<f64> for $t {
            type Output = AffExpr;
            fn mul(self, s: f64) -> AffExpr {
                let mut e: AffExpr = self.into();
                e.scale(s);
                e
            }
        }
        impl Mul<$t> for f64 {
            type Output = AffExpr;
            fn mul(self, e: $t) -> AffExpr {
                e * self
            }
        }
        impl Neg for $t {
            type Output = AffExpr;
            fn neg(self) -> AffExpr {
                self * -1.0
            }
        }
    )*};
}
affine_ops!(AffExpr, &AffExpr, Var);

impl Add<AffExpr> for f64 {
    type Output = AffExpr;
    fn add(self, e: AffExpr) -> AffExpr {
        e + self
    }
}
impl Sub<AffExpr> for f64 {
    type Output = AffExpr;
    fn sub(self, e: AffExpr) -> AffExpr {
        -e + self
    }
}

/// `Σ exprs`.
pub fn sum<I: IntoIterator<Item = AffExpr>>(exprs: I) -> AffExpr {
    exprs.into_iter().sum()
}

impl std::iter::Sum for AffExpr {
    fn sum<I: Iterator<Item = AffExpr>>(iter: I) -> Self {
        iter.fold(AffExpr::zero(), |mut a, e| {
            a += e;
            a
        })
    }
}

impl<'a> std::iter::Sum<&'a AffExpr> for AffExpr {
    fn sum<I: Iterator<Item = &'a AffExpr>>(iter: I) -> Self {
        iter.fold(AffExpr::zero(), |mut a, e| {
            a.axpy(1.0, e);
            a
        })
    }
}

impl std::iter::Sum<Var> for AffExpr {
    fn sum<I: Iterator<Item = Var>>(iter: I) -> Self {
        iter.fold(AffExpr::zero(), |mut a, v| {
            a.add_term(v, 1.0);
            a
        })
    }
}

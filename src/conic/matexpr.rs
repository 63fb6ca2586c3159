//! Affine matrix expressions `M(x) = M₀ + Σ xᵢ Mᵢ`, dense, column-major.
//!
//! Used to write linear matrix inequalities: build `M(x)` from variables,
//! constants, sums, constant congruences `C M Cᵀ`, products with constant
//! matrices and blocks, then constrain it with
//! [`Problem::add_psd`](super::Problem::add_psd). Dimensions are checked and
//! reported as [`ConicError::DimensionMismatch`]; symmetry is checked where a
//! constraint needs it.

use super::error::ConicError;
use super::expr::AffExpr;
use nalgebra::DMatrix;
use std::ops::{Add, Index, IndexMut, Mul, Neg, Sub};

/// A dense `rows × cols` matrix of affine expressions (column-major).
#[derive(Clone, Debug, PartialEq)]
pub struct MatExpr {
    rows: usize,
    cols: usize,
    data: Vec<AffExpr>,
}

fn mismatch(what: &str, expected: (usize, usize), found: (usize, usize)) -> ConicError {
    ConicError::DimensionMismatch {
        what: what.to_string(),
        expected: format!("{}×{}", expected.0, expected.1),
        found: format!("{}×{}", found.0, found.1),
    }
}

/// `rows · cols`; panics when it overflows (a wrapped product would make
/// every later index check disagree with the storage).
fn entry_count(rows: usize, cols: usize) -> usize {
    rows.checked_mul(cols)
        .unwrap_or_else(|| panic!("MatExpr {rows}×{cols}: the number of entries overflows usize"))
}

impl MatExpr {
    /// The `rows × cols` zero matrix; panics if `rows · cols` overflows.
    pub fn zeros(rows: usize, cols: usize) -> Self {
        Self {
            rows,
            cols,
            data: vec![AffExpr::zero(); entry_count(rows, cols)],
        }
    }

    /// Builds entry `(i, j)` from `f(i, j)`; panics if `rows · cols` overflows.
    pub fn from_fn(rows: usize, cols: usize, mut f: impl FnMut(usize, usize) -> AffExpr) -> Self {
        let mut data = Vec::with_capacity(entry_count(rows, cols));
        for j in 0..cols {
            for i in 0..rows {
                data.push(f(i, j));
            }
        }
        Self { rows, cols, data }
    }

    /// A constant matrix.
    pub fn constant(m: &DMatrix<f64>) -> Self {
        Self::from_fn(m.nrows(), m.ncols(), |i, j| AffExpr::constant(m[(i, j)]))
    }

    /// `e · I` of size `n × n`.
    pub fn scaled_identity(n: usize, e: impl Into<AffExpr>) -> Self {
        let e = e.into();
        Self::from_fn(
            n,
            n,
            |i, j| if i == j { e.clone() } else { AffExpr::zero() },
        )
    }

    /// The `n × n` identity.
    pub fn identity(n: usize) -> Self {
        Self::scaled_identity(n, 1.0)
    }

    /// The diagonal matrix with these entries.
    pub fn diag(entries: Vec<AffExpr>) -> Self {
        let n = entries.len();
        let mut m = Self::zeros(n, n);
        for (i, e) in entries.into_iter().enumerate() {
            m.data[i + i * n] = e;
        }
        m
    }

    /// A column vector of expressions.
    pub fn column(entries: Vec<AffExpr>) -> Self {
        Self {
            rows: entries.len(),
            cols: 1,
            data: entries,
        }
    }

    /// Number of rows.
    pub fn nrows(&self) -> usize {
        self.rows
    }

    /// Number of columns.
    pub fn ncols(&self) -> usize {
        self.cols
    }

    /// `(rows, cols)`.
    pub fn shape(&self) -> (usize, usize) {
        (self.rows, self.cols)
    }

    /// Entry `(i, j)`, or an error if out of range.
    pub fn get(&self, i: usize, j: usize) -> Result<&AffExpr, ConicError> {
        if i >= self.rows || j >= self.cols {
            return Err(ConicError::IndexOutOfRange {
                what: format!("entry ({i}, {j})"),
                shape: format!("{}×{}", self.rows, self.cols),
            });
        }
        Ok(&self.data[i + j * self.rows])
    }

    /// Entry `(i, j)` (internal, unchecked beyond the slice bound).
    pub(crate) fn at(&self, i: usize, j: usize) -> &AffExpr {
        &self.data[i + j * self.rows]
    }

    /// Mutable entry `(i, j)`, or an error if out of range.
    pub fn get_mut(&mut self, i: usize, j: usize) -> Result<&mut AffExpr, ConicError> {
        if i >= self.rows || j >= self.cols {
            return Err(ConicError::IndexOutOfRange {
                what: format!("entry ({i}, {j})"),
                shape: format!("{}×{}", self.rows, self.cols),
            });
        }
        Ok(&mut self.data[i + j * self.rows])
    }

    /// All entries, column-major.
    pub fn entries(&self) -> &[AffExpr] {
        &self.data
    }

    /// `self + other`.
    pub fn try_add(&self, other: &MatExpr) -> Result<MatExpr, ConicError> {
        self.zip(other, "matrix sum", 1.0)
    }

    /// `self − other`.
    pub fn try_sub(&self, other: &MatExpr) -> Result<MatExpr, ConicError> {
        self.zip(other, "matrix difference", -1.0)
    }

    fn zip(&self, other: &MatExpr, what: &str, s: f64) -> Result<MatExpr, ConicError> {
        if self.shape() != other.shape() {
            return Err(mismatch(what, self.shape(), other.shape()));
        }
        let data = self
            .data
            .iter()
            .zip(&other.data)
            .map(|(a, b)| {
                let mut e = a.clone();
                e.axpy(s, b);
                e
            })
            .collect();
        Ok(MatExpr {
            rows: self.rows,
            cols: self.cols,
            data,
        })
    }

    /// `s · self`.
    pub fn scaled(&self, s: f64) -> MatExpr {
        let mut m = self.clone();
        m.data.iter_mut().for_each(|e| e.scale(s));
        m
    }

    /// `self + e · I` (square only).
    pub fn plus_identity(&self, e: impl Into<AffExpr>) -> Result<MatExpr, ConicError> {
        self.try_add(&MatExpr::scaled_identity(self.rows, e))
            .map_err(|_| {
                mismatch(
                    "matrix + scalar·I (square matrix)",
                    (self.rows, self.rows),
                    self.shape(),
                )
            })
    }

    /// `Mᵀ`.
    pub fn transpose(&self) -> MatExpr {
        MatExpr::from_fn(self.cols, self.rows, |i, j| self.at(j, i).clone())
    }

    /// `C · M` for a constant `C` (`k × rows`).
    pub fn left_mul(&self, c: &DMatrix<f64>) -> Result<MatExpr, ConicError> {
        if c.ncols() != self.rows {
            return Err(mismatch(
                "constant × matrix expression",
                (c.nrows(), self.rows),
                c.shape(),
            ));
        }
        Ok(MatExpr::from_fn(c.nrows(), self.cols, |i, j| {
            let mut e = AffExpr::zero();
            for k in 0..self.rows {
                let a = c[(i, k)];
                if a != 0.0 {
                    e.axpy(a, self.at(k, j));
                }
            }
            e
        }))
    }

    /// `M · C` for a constant `C` (`cols × k`).
    pub fn right_mul(&self, c: &DMatrix<f64>) -> Result<MatExpr, ConicError> {
        if c.nrows() != self.cols {
            return Err(mismatch(
                "matrix expression × constant",
                (self.cols, c.ncols()),
                c.shape(),
            ));
        }
        Ok(MatExpr::from_fn(self.rows, c.ncols(), |i, j| {
            let mut e = AffExpr::zero();
            for k in 0..self.cols {
                let a = c[(k, j)];
                if a != 0.0 {
                    e.axpy(a, self.at(i, k));
                }
            }
            e
        }))
    }

    /// The congruence `C M Cᵀ`, which keeps a symmetric M symmetric.
    pub fn congruence(&self, c: &DMatrix<f64>) -> Result<MatExpr, ConicError> {
        self.left_mul(c)?.right_mul(&c.transpose())
    }

    /// `tr M`; panics if M is not square ([`MatExpr::try_trace`] returns an error).
    pub fn trace(&self) -> AffExpr {
        self.try_trace()
            .unwrap_or_else(|e| panic!("MatExpr::trace: {e}"))
    }

    /// `tr M` (square only).
    pub fn try_trace(&self) -> Result<AffExpr, ConicError> {
        if self.rows != self.cols {
            return Err(mismatch(
                "trace (square matrix)",
                (self.rows, self.rows),
                self.shape(),
            ));
        }
        let mut e = AffExpr::zero();
        for i in 0..self.rows {
            e += self.at(i, i);
        }
        Ok(e)
    }

    /// The diagonal entries (square or not: `min(rows, cols)` of them).
    pub fn diagonal(&self) -> Vec<AffExpr> {
        (0..self.rows.min(self.cols))
            .map(|i| self.at(i, i).clone())
            .collect()
    }

    /// `Σᵢⱼ Mᵢⱼ`.
    pub fn sum(&self) -> AffExpr {
        self.data.iter().sum()
    }

    /// The inner product `⟨C, M⟩ = Σᵢⱼ Cᵢⱼ Mᵢⱼ = tr(Cᵀ M)`; panics on a shape
    /// mismatch ([`MatExpr::try_dot`] returns an error).
    pub fn dot(&self, c: &DMatrix<f64>) -> AffExpr {
        self.try_dot(c)
            .unwrap_or_else(|e| panic!("MatExpr::dot: {e}"))
    }

    /// The inner product `⟨C, M⟩`, or an error on a shape mismatch.
    pub fn try_dot(&self, c: &DMatrix<f64>) -> Result<AffExpr, ConicError> {
        if c.shape() != self.shape() {
            return Err(mismatch("inner product ⟨C, M⟩", self.shape(), c.shape()));
        }
        let mut e = AffExpr::zero();
        for j in 0..self.cols {
            for i in 0..self.rows {
                let a = c[(i, j)];
                if a != 0.0 {
                    e.axpy(a, self.at(i, j));
                }
            }
        }
        Ok(e)
    }

    /// The block matrix `[[B₀₀, B₀₁, …], [B₁₀, …], …]`; `None` is a zero block
    /// whose size is taken from the other blocks of its row and column.
    pub fn block(blocks: &[Vec<Option<&MatExpr>>]) -> Result<MatExpr, ConicError> {
        let (h, w) = block_sizes(blocks)?;
        let mut out = MatExpr::zeros(h.iter().sum(), w.iter().sum());
        let mut r0 = 0;
        for (bi, row) in blocks.iter().enumerate() {
            let mut c0 = 0;
            for (bj, b) in row.iter().enumerate() {
                if let Some(b) = b {
                    for j in 0..b.cols {
                        for i in 0..b.rows {
                            out.data[(r0 + i) + (c0 + j) * out.rows] = b.at(i, j).clone();
                        }
                    }
                }
                c0 += w[bj];
            }
            r0 += h[bi];
        }
        Ok(out)
    }

    /// `[A B]`.
    pub fn hstack(a: &MatExpr, b: &MatExpr) -> Result<MatExpr, ConicError> {
        Self::block(&[vec![Some(a), Some(b)]])
    }

    /// `[A; B]`.
    pub fn vstack(a: &MatExpr, b: &MatExpr) -> Result<MatExpr, ConicError> {
        Self::block(&[vec![Some(a)], vec![Some(b)]])
    }

    /// Whether `M = Mᵀ` coefficient-wise within `tol`. Returns the first
    /// offending `(i, j)` otherwise.
    pub fn symmetry_defect(&self, tol: f64) -> Option<(usize, usize)> {
        if self.rows != self.cols {
            return Some((self.rows, self.cols));
        }
        for j in 0..self.cols {
            for i in 0..j {
                if !self.at(i, j).approx_eq(self.at(j, i), tol) {
                    return Some((i, j));
                }
            }
        }
        None
    }

    /// Value at the primal point `x`.
    pub fn eval(&self, x: &[f64]) -> DMatrix<f64> {
        DMatrix::from_fn(self.rows, self.cols, |i, j| self.at(i, j).eval(x))
    }

    /// Whether every coefficient is finite.
    pub fn is_finite(&self) -> bool {
        self.data.iter().all(AffExpr::is_finite)
    }
}

/// Operators panic on a shape mismatch (as nalgebra's do); the `try_`
/// methods return [`ConicError::DimensionMismatch`] instead.
fn or_panic(r: Result<MatExpr, ConicError>, op: &str) -> MatExpr {
    r.unwrap_or_else(|e| panic!("MatExpr {op}: {e}"))
}

impl Add<&MatExpr> for &MatExpr {
    type Output = MatExpr;
    fn add(self, rhs: &MatExpr) -> MatExpr {
        or_panic(self.try_add(rhs), "+")
    }
}
impl Sub<&MatExpr> for &MatExpr {
    type Output = MatExpr;
    fn sub(self, rhs: &MatExpr) -> MatExpr {
        or_panic(self.try_sub(rhs), "−")
    }
}
impl Add<MatExpr> for MatExpr {
    type Output = MatExpr;
    fn add(self, rhs: MatExpr) -> MatExpr {
        &self + &rhs
    }
}
impl Sub<MatExpr> for MatExpr {
    type Output = MatExpr;
    fn sub(self, rhs: MatExpr) -> MatExpr {
        &self - &rhs
    }
}
impl Add<&MatExpr> for MatExpr {
    type Output = MatExpr;
    fn add(self, rhs: &MatExpr) -> MatExpr {
        &self + rhs
    }
}
impl Sub<&MatExpr> for MatExpr {
    type Output = MatExpr;
    fn sub(self, rhs: &MatExpr) -> MatExpr {
        &self - rhs
    }
}
impl Mul<f64> for &MatExpr {
    type Output = MatExpr;
    fn mul(self, s: f64) -> MatExpr {
        self.scaled(s)
    }
}
impl Mul<f64> for MatExpr {
    type Output = MatExpr;
    fn mul(self, s: f64) -> MatExpr {
        self.scaled(s)
    }
}
impl Mul<&MatExpr> for f64 {
    type Output = MatExpr;
    fn mul(self, m: &MatExpr) -> MatExpr {
        m.scaled(self)
    }
}
impl Mul<&MatExpr> for &DMatrix<f64> {
    type Output = MatExpr;
    fn mul(self, m: &MatExpr) -> MatExpr {
        or_panic(m.left_mul(self), "constant × expression")
    }
}
impl Mul<&DMatrix<f64>> for &MatExpr {
    type Output = MatExpr;
    fn mul(self, c: &DMatrix<f64>) -> MatExpr {
        or_panic(self.right_mul(c), "expression × constant")
    }
}
impl Index<(usize, usize)> for MatExpr {
    type Output = AffExpr;
    /// Entry `(i, j)`; panics out of range ([`MatExpr::get`] returns an error).
    fn index(&self, (i, j): (usize, usize)) -> &AffExpr {
        assert!(
            i < self.rows && j < self.cols,
            "MatExpr index ({i}, {j}) out of range for {}×{}",
            self.rows,
            self.cols
        );
        &self.data[i + j * self.rows]
    }
}
impl IndexMut<(usize, usize)> for MatExpr {
    fn index_mut(&mut self, (i, j): (usize, usize)) -> &mut AffExpr {
        assert!(
            i < self.rows && j < self.cols,
            "MatExpr index ({i}, {j}) out of range for {}×{}",
            self.rows,
            self.cols
        );
        &mut self.data[i + j * self.rows]
    }
}
impl From<&MatExpr> for MatExpr {
    fn from(m: &MatExpr) -> MatExpr {
        m.clone()
    }
}
impl Neg for &MatExpr {
    type Output = MatExpr;
    fn neg(self) -> MatExpr {
        self.scaled(-1.0)
    }
}
impl Neg for MatExpr {
    type Output = MatExpr;
    fn neg(self) -> MatExpr {
        self.scaled(-1.0)
    }
}
impl Add<MatExpr> for &MatExpr {
    type Output = MatExpr;
    fn add(self, rhs: MatExpr) -> MatExpr {
        self + &rhs
    }
}
impl Sub<MatExpr> for &MatExpr {
    type Output = MatExpr;
    fn sub(self, rhs: MatExpr) -> MatExpr {
        self - &rhs
    }
}
impl Mul<MatExpr> for f64 {
    type Output = MatExpr;
    fn mul(self, m: MatExpr) -> MatExpr {
        m.scaled(self)
    }
}
impl Mul<MatExpr> for &DMatrix<f64> {
    type Output = MatExpr;
    fn mul(self, m: MatExpr) -> MatExpr {
        self * &m
    }
}
impl Mul<&DMatrix<f64>> for MatExpr {
    type Output = MatExpr;
    fn mul(self, c: &DMatrix<f64>) -> MatExpr {
        &self * c
    }
}

/// The heights of a block matrix's rows and the widths of its columns,
/// each fixed by its non-empty blocks (which must agree).
fn block_sizes(blocks: &[Vec<Option<&MatExpr>>]) -> Result<(Vec<usize>, Vec<usize>), ConicError> {
    let nr = blocks.len();
    let nc = blocks.first().map_or(0, |r| r.len());
    if nr == 0 || nc == 0 {
        return Err(ConicError::DimensionMismatch {
            what: "block matrix".into(),
            expected: "at least one block".into(),
            found: "none".into(),
        });
    }
    let mut heights = vec![None; nr];
    let mut widths = vec![None; nc];
    for (bi, row) in blocks.iter().enumerate() {
        if row.len() != nc {
            return Err(ConicError::DimensionMismatch {
                what: format!("block row {bi}"),
                expected: format!("{nc} blocks"),
                found: format!("{} blocks", row.len()),
            });
        }
        for (bj, b) in row.iter().enumerate() {
            if let Some(b) = b {
                fix(&mut heights[bi], b.rows, (bi, bj), || {
                    format!("height of block row {bi}")
                })?;
                fix(&mut widths[bj], b.cols, (bi, bj), || {
                    format!("width of block column {bj}")
                })?;
            }
        }
    }
    let undetermined = |v: &[Option<usize>], what: &str| {
        v.iter()
            .position(Option::is_none)
            .map(|i| ConicError::DimensionMismatch {
                what: format!("{what} {i} of block matrix"),
                expected: "a non-empty block to fix its size".into(),
                found: "only zero blocks".into(),
            })
    };
    if let Some(e) = undetermined(&heights, "block row").or(undetermined(&widths, "block column")) {
        return Err(e);
    }
    Ok((
        heights.into_iter().flatten().collect(),
        widths.into_iter().flatten().collect(),
    ))
}

/// A block row's height (or column's width) set by block `at`'s `val`, or
/// the mismatch with the one set before.
fn fix(
    slot: &mut Option<usize>,
    val: usize,
    (bi, bj): (usize, usize),
    what: impl Fn() -> String,
) -> Result<(), ConicError> {
    match *slot {
        None => *slot = Some(val),
        Some(v) if v != val => {
            return Err(ConicError::DimensionMismatch {
                what: what(),
                expected: v.to_string(),
                found: format!("{val} in block ({bi}, {bj})"),
            });
        }
        _ => {}
    }
    Ok(())
}

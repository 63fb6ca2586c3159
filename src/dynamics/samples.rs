//! A sequence of joint-space vectors (q, q̇, q̈ or τ of every sample) in
//! one row-major buffer: `samples × width`, no allocation per sample.

use std::ops::{Index, IndexMut, Range};

/// `len()` rows of `width()` values each (one row per sample, one value
/// per joint), stored row-major in one buffer.
///
/// `s[k]` is sample k's row (`&[f64]` of length `width()`); [`Samples::column`]
/// gives one joint's series.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Samples {
    width: usize,
    rows: usize,
    data: Vec<f64>,
}

impl Samples {
    /// No rows, of `width` values each.
    pub fn new(width: usize) -> Self {
        Self {
            width,
            rows: 0,
            data: vec![],
        }
    }

    /// No rows, with room for `rows` of `width` values.
    pub fn with_capacity(width: usize, rows: usize) -> Self {
        Self {
            width,
            rows: 0,
            data: Vec::with_capacity(width.saturating_mul(rows)),
        }
    }

    /// `rows` rows of `width` zeros.
    pub fn zeros(rows: usize, width: usize) -> Self {
        Self {
            width,
            rows,
            data: vec![0.0; rows * width],
        }
    }

    /// Rows from a row-major buffer; `None` when `data.len()` is not a
    /// multiple of `width` (or `width` is 0 and `data` is not empty).
    pub fn from_flat(width: usize, data: Vec<f64>) -> Option<Self> {
        match (width, data.len()) {
            (0, 0) => Some(Self::new(0)),
            (0, _) => None,
            (w, l) if l % w == 0 => Some(Self {
                width: w,
                rows: l / w,
                data,
            }),
            _ => None,
        }
    }

    /// Rows from per-row vectors (all of one length; none: width 0).
    ///
    /// # Panics
    /// If the rows differ in length (a programming error: readers of user
    /// files check their rows and name the bad one).
    pub fn from_rows<R: AsRef<[f64]>>(rows: &[R]) -> Self {
        let width = rows.first().map_or(0, |r| r.as_ref().len());
        let mut s = Self::with_capacity(width, rows.len());
        for r in rows {
            s.push(r.as_ref());
        }
        s
    }

    /// Values per row.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.rows
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.rows == 0
    }

    /// Removes every row (keeping the room, for reuse).
    pub fn clear(&mut self) {
        self.data.clear();
        self.rows = 0;
    }

    /// Appends one row.
    ///
    /// # Panics
    /// If `row.len() != self.width()`.
    pub fn push(&mut self, row: &[f64]) {
        assert_eq!(row.len(), self.width, "a row of {} values", self.width);
        self.data.extend_from_slice(row);
        self.rows += 1;
    }

    /// Appends one row of values `f(j)`, `j < width`.
    pub fn push_with(&mut self, f: impl FnMut(usize) -> f64) {
        self.data.extend((0..self.width).map(f));
        self.rows += 1;
    }

    /// Appends one row of values `f(j)`, `j < width`, unless one is an
    /// error (then nothing is appended and the first error returned).
    pub fn try_push_with<E>(
        &mut self,
        mut f: impl FnMut(usize) -> Result<f64, E>,
    ) -> Result<(), E> {
        let start = self.data.len();
        for j in 0..self.width {
            match f(j) {
                Ok(v) => self.data.push(v),
                Err(e) => {
                    self.data.truncate(start);
                    return Err(e);
                }
            }
        }
        self.rows += 1;
        Ok(())
    }

    /// The rows, in order.
    pub fn iter(&self) -> RowIter<'_> {
        RowIter {
            data: &self.data,
            width: self.width,
            left: self.rows,
        }
    }

    /// The rows, mutable, in order.
    pub fn iter_mut(&mut self) -> impl Iterator<Item = &mut [f64]> {
        self.data.chunks_exact_mut(self.width.max(1))
    }

    /// Column `j` (one joint's series), copied.
    pub fn column(&self, j: usize) -> Vec<f64> {
        self.iter().map(|r| r[j]).collect()
    }

    /// The row-major buffer (`len() · width()` values).
    pub fn as_flat(&self) -> &[f64] {
        &self.data
    }

    /// The row-major buffer, mutable.
    pub fn as_flat_mut(&mut self) -> &mut [f64] {
        &mut self.data
    }

    /// Rows `range` as new samples.
    pub fn slice(&self, range: Range<usize>) -> Samples {
        let w = self.width;
        Samples {
            width: w,
            rows: range.len(),
            data: self.data[range.start * w..range.end * w].to_vec(),
        }
    }

    /// Keeps only rows `range`, in place.
    pub fn keep(&mut self, range: Range<usize>) {
        let w = self.width;
        let end = range.end.min(self.rows);
        let start = range.start.min(end);
        self.data.truncate(end * w);
        self.data.drain(..start * w);
        self.rows = end - start;
    }

    /// Moves `other`'s rows to the end of these.
    ///
    /// # Panics
    /// If both have rows and their widths differ.
    pub fn append(&mut self, other: &mut Samples) {
        if self.rows == 0 && self.data.is_empty() {
            self.width = other.width;
        }
        assert!(
            other.rows == 0 || other.width == self.width,
            "appending rows of {} values to rows of {}",
            other.width,
            self.width
        );
        self.data.append(&mut other.data);
        self.rows += std::mem::take(&mut other.rows);
    }

    /// The rows as vectors (for callers that want them so).
    pub fn to_rows(&self) -> Vec<Vec<f64>> {
        self.iter().map(<[f64]>::to_vec).collect()
    }
}

/// The rows of [`Samples`], in order.
#[derive(Clone, Debug)]
pub struct RowIter<'a> {
    data: &'a [f64],
    width: usize,
    left: usize,
}

impl<'a> Iterator for RowIter<'a> {
    type Item = &'a [f64];

    fn next(&mut self) -> Option<&'a [f64]> {
        if self.left == 0 {
            return None;
        }
        let (row, rest) = self.data.split_at(self.width);
        self.data = rest;
        self.left -= 1;
        Some(row)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        (self.left, Some(self.left))
    }
}

impl ExactSizeIterator for RowIter<'_> {}

impl<'a> DoubleEndedIterator for RowIter<'a> {
    fn next_back(&mut self) -> Option<&'a [f64]> {
        if self.left == 0 {
            return None;
        }
        let (rest, row) = self.data.split_at(self.data.len() - self.width);
        self.data = rest;
        self.left -= 1;
        Some(row)
    }
}

impl<'a> IntoIterator for &'a Samples {
    type Item = &'a [f64];
    type IntoIter = RowIter<'a>;

    fn into_iter(self) -> RowIter<'a> {
        self.iter()
    }
}

impl Index<usize> for Samples {
    type Output = [f64];

    fn index(&self, k: usize) -> &[f64] {
        assert!(k < self.rows, "row {k} of {}", self.rows);
        &self.data[k * self.width..(k + 1) * self.width]
    }
}

impl IndexMut<usize> for Samples {
    fn index_mut(&mut self, k: usize) -> &mut [f64] {
        assert!(k < self.rows, "row {k} of {}", self.rows);
        &mut self.data[k * self.width..(k + 1) * self.width]
    }
}

impl serde::Serialize for Samples {
    /// As a sequence of rows.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.iter())
    }
}

impl FromIterator<Vec<f64>> for Samples {
    /// # Panics
    /// If the rows differ in length.
    fn from_iter<I: IntoIterator<Item = Vec<f64>>>(it: I) -> Self {
        let mut it = it.into_iter().peekable();
        let width = it.peek().map_or(0, Vec::len);
        let mut s = Samples::with_capacity(width, it.size_hint().0);
        for r in it {
            s.push(&r);
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::Samples;

    #[test]
    fn rows_round_trip_and_edit_in_place() {
        let rows = vec![vec![1.0, 2.0], vec![3.0, 4.0], vec![5.0, 6.0]];
        let mut s = Samples::from_rows(&rows);
        assert_eq!((s.len(), s.width()), (3, 2));
        assert_eq!(&s[1], &[3.0, 4.0]);
        assert_eq!(s.to_rows(), rows);
        assert_eq!(s.column(1), vec![2.0, 4.0, 6.0]);
        assert_eq!(s.iter().rev().next(), Some(&[5.0, 6.0][..]));
        assert_eq!(s.slice(1..3).to_rows(), rows[1..3].to_vec());
        s.keep(1..2);
        assert_eq!(s.to_rows(), vec![vec![3.0, 4.0]]);
        let mut more = Samples::from_rows(&[[7.0, 8.0]]);
        s.append(&mut more);
        assert!(more.is_empty());
        assert_eq!(s.to_rows(), vec![vec![3.0, 4.0], vec![7.0, 8.0]]);
        let collected: Samples = rows.clone().into_iter().collect();
        assert_eq!(collected.to_rows(), rows);
        assert!(Samples::from_flat(2, vec![1.0; 3]).is_none());
        assert_eq!(
            Samples::from_flat(2, vec![1.0; 4]).map(|s| s.len()),
            Some(2)
        );
    }

    #[test]
    #[should_panic(expected = "a row of 2 values")]
    fn a_ragged_row_is_refused() {
        Samples::from_rows(&[vec![1.0, 2.0], vec![3.0]]);
    }
}

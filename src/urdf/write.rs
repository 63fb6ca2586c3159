//! Writing a copy of URDF text: elements replaced or inserted at byte
//! ranges of the original (from [`super::read_str`]), every other byte kept.

use std::ops::Range;

/// An edit of the text: the bytes of `range` replaced by `text` (an empty
/// range inserts).
pub type Edit = (Range<usize>, String);

/// `text` with `edits` applied in one pass, in file order; `None` when two
/// of them overlap or one lies outside the text (edits not of this text).
pub fn apply_edits(text: &str, mut edits: Vec<Edit>) -> Option<String> {
    edits.sort_by_key(|e| (e.0.start, e.0.end));
    let extra = edits.iter().map(|e| e.1.len()).sum::<usize>();
    let mut out = String::with_capacity(text.len() + extra);
    let mut at = 0;
    for (r, s) in edits {
        if r.start < at || r.end < r.start || !text.is_char_boundary(r.end) {
            return None;
        }
        out.push_str(text.get(at..r.start)?);
        out.push_str(&s);
        at = r.end;
    }
    out.push_str(text.get(at..)?);
    Some(out)
}

/// An `<inertial>` element (mass in kg, `com` the CoM in the link frame in
/// m, `inertia` `[ixx, ixy, ixz, iyy, iyz, izz]` about the CoM in the link
/// frame's axes in kg·m², so `rpy="0 0 0"`), with `comment` as its first
/// child and its lines indented by `pad`. Numbers are written in Rust's
/// shortest form that reads back to the same `f64`.
pub fn inertial_xml(
    pad: &str,
    comment: &str,
    mass: f64,
    com: [f64; 3],
    inertia: [f64; 6],
) -> String {
    let [x, y, z] = com;
    let [ixx, ixy, ixz, iyy, iyz, izz] = inertia;
    format!(
        "<inertial>\n{pad}  <!-- {comment} -->\n{pad}  <origin xyz=\"{x:e} {y:e} {z:e}\" rpy=\"0 0 0\"/>\n{pad}  <mass value=\"{mass:e}\"/>\n{pad}  <inertia ixx=\"{ixx:e}\" ixy=\"{ixy:e}\" ixz=\"{ixz:e}\" iyy=\"{iyy:e}\" iyz=\"{iyz:e}\" izz=\"{izz:e}\"/>\n{pad}</inertial>"
    )
}

/// The spaces and tabs between the start of the line and byte `at`, if
/// only those precede it on its line (else ""); looks back no further than
/// the indentation, so that many edits on one long line stay linear.
pub fn indent_before(text: &str, at: usize) -> &str {
    let b = text.as_bytes();
    let mut i = at.min(b.len());
    while i > 0 && matches!(b[i - 1], b' ' | b'\t') {
        i -= 1;
    }
    if i == 0 || b[i - 1] == b'\n' {
        &text[i..at]
    } else {
        ""
    }
}

#[cfg(test)]
mod tests {
    use super::apply_edits;

    /// Edits land where they say, in any order given; overlapping ones and
    /// ones past the end are refused.
    #[test]
    fn edits_apply_in_file_order() {
        let text = "<a><b/><c/></a>";
        let edits = vec![
            (7..11, "<C/>".to_string()),
            (3..3, "<x/>".into()),
            (3..7, "".into()),
        ];
        assert_eq!(apply_edits(text, edits).unwrap(), "<a><x/><C/></a>");
        assert!(apply_edits(text, vec![(3..8, "".into()), (7..9, "".into())]).is_none());
        assert!(apply_edits(text, vec![(14..20, "".into())]).is_none());
    }
}

//! Limits on URDF text, checked in one pass over the bytes before the XML
//! parser builds anything: the file size, the number of nodes, the nesting
//! depth, the attributes per element and the namespace declarations. Each
//! bounds work or memory that would otherwise grow faster than the file
//! (roxmltree compares every attribute of an element with the ones before
//! it, and copies the namespaces in scope into every element that declares
//! one) or become large for its size (some 75 bytes per node: a file of
//! `<a/>` takes about 19 times its size).
//!
//! The pass is not a validator: it tells markup from text (comments, CDATA,
//! processing instructions, quoted attribute values) and counts; whatever is
//! malformed is left for the parser to report.

use super::error::UrdfError;

/// Default largest file: 256 MiB.
pub const MAX_BYTES: usize = 256 << 20;
/// Default most nodes (elements, comments, processing instructions, CDATA
/// sections): 16 Mi, about 1.2 GB of parsed document.
pub const MAX_NODES: usize = 16 << 20;
/// Default deepest nesting of elements (`<robot>` is depth 1).
pub const MAX_DEPTH: usize = 1_000;
/// Default most attributes on one element.
pub const MAX_ATTRIBUTES: usize = 64;
/// Default most namespace declarations (`xmlns`, `xmlns:p`) in a file.
pub const MAX_NAMESPACES: usize = 1_000;

/// What the reader accepts; beyond each limit the file is refused with a
/// named [`UrdfError`] ([`UrdfError::TooLarge`], [`UrdfError::TooDeep`],
/// [`UrdfError::TooManyNodes`], [`UrdfError::TooManyAttributes`],
/// [`UrdfError::TooManyNamespaces`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Largest file (bytes); default [`MAX_BYTES`] (256 MiB).
    pub max_bytes: usize,
    /// Most nodes (elements, comments, processing instructions, CDATA
    /// sections); default [`MAX_NODES`].
    pub max_nodes: usize,
    /// Deepest element nesting; default [`MAX_DEPTH`].
    pub max_depth: usize,
    /// Most attributes on one element; default [`MAX_ATTRIBUTES`].
    pub max_attributes: usize,
    /// Most namespace declarations in the file; default [`MAX_NAMESPACES`].
    pub max_namespaces: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_bytes: MAX_BYTES,
            max_nodes: MAX_NODES,
            max_depth: MAX_DEPTH,
            max_attributes: MAX_ATTRIBUTES,
            max_namespaces: MAX_NAMESPACES,
        }
    }
}

/// Which limit a text exceeds, and the byte offset where.
#[derive(Debug, PartialEq, Eq)]
enum Exceeded {
    Nodes(usize),
    Depth(usize),
    Attributes(usize),
    Namespaces(usize),
}

/// A start tag: where it ends, its attributes and namespace declarations,
/// and whether it is empty (`<a/>`).
struct StartTag {
    end: usize,
    attributes: usize,
    namespaces: usize,
    empty: bool,
}

/// The offset just past the first `needle` at or after `from` (the end of
/// the text if there is none).
fn past(b: &[u8], from: usize, needle: &[u8]) -> usize {
    let from = from.min(b.len());
    b[from..]
        .windows(needle.len())
        .position(|w| w == needle)
        .map_or(b.len(), |p| from + p + needle.len())
}

fn is_space(c: u8) -> bool {
    matches!(c, b' ' | b'\t' | b'\n' | b'\r')
}

fn skip_spaces(b: &[u8], mut i: usize) -> usize {
    while i < b.len() && is_space(b[i]) {
        i += 1;
    }
    i
}

/// One attribute from `i` (its first byte is neither a space, `/` nor `>`):
/// the offset after it and whether it declares a namespace.
fn attribute(b: &[u8], mut i: usize) -> (usize, bool) {
    let start = i;
    while i < b.len() && !(is_space(b[i]) || matches!(b[i], b'=' | b'>' | b'/')) {
        i += 1;
    }
    let name = &b[start..i];
    let xmlns = name == b"xmlns" || name.starts_with(b"xmlns:");
    i = skip_spaces(b, i);
    if i < b.len() && b[i] == b'=' {
        i = skip_spaces(b, i + 1);
        if i < b.len() && matches!(b[i], b'"' | b'\'') {
            i = past(b, i + 1, &[b[i]]);
        }
    }
    // always move on, malformed or not
    (i.max(start + 1), xmlns)
}

/// The start tag whose name begins at `i` (just after `<`).
fn start_tag(b: &[u8], mut i: usize) -> StartTag {
    while i < b.len() && !(is_space(b[i]) || matches!(b[i], b'/' | b'>')) {
        i += 1;
    }
    let (mut attributes, mut namespaces) = (0, 0);
    loop {
        i = skip_spaces(b, i);
        let empty = match b.get(i) {
            None => false,
            Some(b'>') => false,
            Some(b'/') if b.get(i + 1) == Some(&b'>') => true,
            Some(b'/') => {
                i += 1;
                continue;
            }
            Some(_) => {
                let (next, xmlns) = attribute(b, i);
                attributes += 1;
                namespaces += usize::from(xmlns);
                i = next;
                continue;
            }
        };
        let end = (i + 1 + usize::from(empty)).min(b.len());
        return StartTag {
            end,
            attributes,
            namespaces,
            empty,
        };
    }
}

/// The first limit `text` exceeds, if any.
fn scan(text: &str, limits: &Limits) -> Option<Exceeded> {
    let b = text.as_bytes();
    let (mut i, mut depth, mut namespaces, mut nodes) = (0, 0usize, 0usize, 0usize);
    while let Some(p) = b[i..].iter().position(|&c| c == b'<') {
        let at = i + p;
        let rest = &b[at..];
        if !rest.starts_with(b"</") {
            nodes += 1;
            if nodes > limits.max_nodes {
                return Some(Exceeded::Nodes(at));
            }
        }
        i = if rest.starts_with(b"<!--") {
            past(b, at + 4, b"-->")
        } else if rest.starts_with(b"<![CDATA[") {
            past(b, at + 9, b"]]>")
        } else if rest.starts_with(b"<?") {
            past(b, at + 2, b"?>")
        } else if rest.starts_with(b"<!") {
            // a DTD, which the parser refuses
            past(b, at + 2, b">")
        } else if rest.starts_with(b"</") {
            depth = depth.saturating_sub(1);
            past(b, at + 2, b">")
        } else {
            let tag = start_tag(b, at + 1);
            if tag.attributes > limits.max_attributes {
                return Some(Exceeded::Attributes(at));
            }
            namespaces += tag.namespaces;
            if namespaces > limits.max_namespaces {
                return Some(Exceeded::Namespaces(at));
            }
            // an empty element is as deep as one with content
            if depth + 1 > limits.max_depth {
                return Some(Exceeded::Depth(at));
            }
            depth += usize::from(!tag.empty);
            tag.end
        };
    }
    None
}

/// The 1-based line of byte `offset`.
fn line_at(text: &str, offset: usize) -> usize {
    1 + text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&c| c == b'\n')
        .count()
}

/// Refuses `text` beyond `limits`, naming the limit and the line.
pub(super) fn check(text: &str, path: &str, limits: &Limits) -> Result<(), UrdfError> {
    if text.len() > limits.max_bytes {
        return Err(UrdfError::TooLarge {
            path: path.into(),
            bytes: text.len() as u64,
            limit: limits.max_bytes,
        });
    }
    let path = path.to_string();
    match scan(text, limits) {
        None => Ok(()),
        Some(Exceeded::Nodes(at)) => Err(UrdfError::TooManyNodes {
            path,
            line: line_at(text, at),
            limit: limits.max_nodes,
        }),
        Some(Exceeded::Depth(at)) => Err(UrdfError::TooDeep {
            path,
            line: line_at(text, at),
            limit: limits.max_depth,
        }),
        Some(Exceeded::Attributes(at)) => Err(UrdfError::TooManyAttributes {
            path,
            line: line_at(text, at),
            limit: limits.max_attributes,
        }),
        Some(Exceeded::Namespaces(at)) => Err(UrdfError::TooManyNamespaces {
            path,
            line: line_at(text, at),
            limit: limits.max_namespaces,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> Limits {
        Limits {
            max_bytes: 1 << 20,
            max_nodes: 12,
            max_depth: 3,
            max_attributes: 2,
            max_namespaces: 1,
        }
    }

    #[test]
    fn depth_counts_elements_not_markup_in_text() {
        let ok = "<?xml version=\"1.0\"?><!-- <a><a><a><a> --><r><a x=\"<b><b>\" y='>'><b/><b/>\
                  <![CDATA[<c><c><c>]]><c></c></a></r>";
        assert_eq!(scan(ok, &small()), None);
        let many = "<r><a/><!-- --><?p?><![CDATA[x]]><a/><a/><a/><a/><a/><a/><a/><a/></r>";
        assert_eq!(scan(many, &small()), Some(Exceeded::Nodes(61)));
        let deep = "<r>\n<a>\n<b>\n<c></c></b></a></r>";
        assert_eq!(scan(deep, &small()), Some(Exceeded::Depth(12)));
        let e = check(deep, "d.urdf", &small()).unwrap_err().to_string();
        assert_eq!(e, "d.urdf: line 4: elements nested more than 3 deep");
    }

    #[test]
    fn attributes_and_namespaces_are_counted() {
        assert_eq!(scan("<r a='1' b=\"2\"/>", &small()), None);
        assert_eq!(
            scan("<r a='1' b=\"2\" c='3'/>", &small()),
            Some(Exceeded::Attributes(0))
        );
        assert_eq!(scan("<r xmlns:x='u'><x:a/></r>", &small()), None);
        assert_eq!(
            scan("<r xmlns:x='u'><a xmlns='v'/></r>", &small()),
            Some(Exceeded::Namespaces(15))
        );
    }

    #[test]
    fn malformed_text_ends_the_scan_without_a_verdict() {
        for t in [
            "<", "<a", "<a b", "<a b=", "<a b='", "</", "<!--", "<a/", "<a =x/>", "<<<>>>",
        ] {
            assert_eq!(scan(t, &small()), None, "{t}");
        }
        let big = "x".repeat(10);
        let lim = Limits {
            max_bytes: 9,
            ..small()
        };
        assert!(matches!(
            check(&big, "b.urdf", &lim),
            Err(UrdfError::TooLarge {
                bytes: 10,
                limit: 9,
                ..
            })
        ));
    }
}

//! The JSON form every module's warnings share: a warning enum derives
//! `Serialize` with `#[serde(tag = "kind")]` and implements `Display`; a
//! result's `warnings` field serialises through [`with_messages`], so each
//! warning is `{"kind": …, its values…, "message": its sentence}`.

use serde::Serialize;
use std::fmt;

/// Serialises warnings as their tagged fields plus `message`, their
/// sentence (for `#[serde(serialize_with)]`).
pub(crate) fn with_messages<W, S>(warnings: &[W], s: S) -> Result<S::Ok, S::Error>
where
    W: Serialize + fmt::Display,
    S: serde::Serializer,
{
    use serde::ser::{Error, SerializeSeq};
    let mut seq = s.serialize_seq(Some(warnings.len()))?;
    for w in warnings {
        let mut v = serde_json::to_value(w).map_err(S::Error::custom)?;
        if let Some(m) = v.as_object_mut() {
            m.insert("message".into(), w.to_string().into());
        }
        seq.serialize_element(&v)?;
    }
    seq.end()
}

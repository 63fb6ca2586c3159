//! What reading a log skipped or substituted without failing.

use serde::Serialize;
use std::fmt;

/// A warning about one log file as read.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum ReadWarning {
    /// Messages on the topic that name none of the robot's joints (another
    /// publisher's) were skipped.
    MessagesSkipped {
        /// The topic.
        topic: String,
        /// How many.
        count: usize,
    },
    /// Every message's header stamp is zero: the times the messages were
    /// logged at are used instead.
    LogTimesUsed {
        /// The topic.
        topic: String,
    },
}

impl fmt::Display for ReadWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadWarning::MessagesSkipped { topic, count } => write!(
                f,
                "{topic}: {count} messages naming none of the robot's joints skipped"
            ),
            ReadWarning::LogTimesUsed { topic } => write!(
                f,
                "{topic}: every header stamp is zero; the messages' log times are used"
            ),
        }
    }
}

//! ROS 2 bags in MCAP (ROS 2's default storage): the
//! `sensor_msgs/msg/JointState` messages of one topic, CDR-encoded, read
//! with the `mcap` and `cdr-encoding` crates.
//!
//! Each message gives one row: its header's stamp (s; a bag whose stamps
//! are all zero uses the messages' log times, with a warning), and the
//! `position`, `velocity` and `effort` of the robot's joints, matched by
//! name (SI units, as the message defines them). A message that names
//! none of the robot's joints (another publisher's on the same topic) is
//! skipped and counted in a warning; one that names some but not all is an
//! error. Of a [`Mapping`], only `topic` applies (default: the bag's only
//! JointState topic).

use super::error::DataError;
use super::mapping::Mapping;
use super::raw::{MAX_ABS_VALUE, MAX_ROWS, RawLog, check_value};
use super::warning::ReadWarning;
use crate::dynamics::Samples;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The largest bag read (bytes): it is read whole.
pub const MAX_BAG_BYTES: u64 = 4 << 30;

/// The message type read.
pub const JOINT_STATE: &str = "sensor_msgs/msg/JointState";

/// `builtin_interfaces/msg/Time`.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq)]
pub struct Time {
    /// Seconds.
    pub sec: i32,
    /// Nanoseconds, in [0, 1e9).
    pub nanosec: u32,
}

/// `std_msgs/msg/Header`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
pub struct Header {
    /// When the state was measured.
    pub stamp: Time,
    /// The frame (unused).
    pub frame_id: String,
}

/// `sensor_msgs/msg/JointState`: per named joint its position (rad or m),
/// velocity (rad/s or m/s) and effort (N·m or N); `velocity` and `effort`
/// may be empty.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
pub struct JointState {
    /// The stamp.
    pub header: Header,
    /// The joints' names.
    pub name: Vec<String>,
    /// Positions.
    pub position: Vec<f64>,
    /// Velocities (or none).
    pub velocity: Vec<f64>,
    /// Efforts (or none).
    pub effort: Vec<f64>,
}

impl JointState {
    /// The message CDR-encoded as ROS 2 stores it (little-endian, after the
    /// 4-byte encapsulation header).
    pub fn to_cdr(&self) -> Result<Vec<u8>, cdr_encoding::Error> {
        let mut out = vec![0, 1, 0, 0];
        out.extend(cdr_encoding::to_vec::<_, byteorder::LittleEndian>(self)?);
        Ok(out)
    }

    /// Decodes a CDR message (either byte order, from its header).
    pub fn from_cdr(data: &[u8]) -> Result<Self, cdr_encoding::Error> {
        let (head, body) = data.split_at_checked(4).ok_or(cdr_encoding::Error::Eof)?;
        let r = match head[1] {
            0 => cdr_encoding::from_bytes::<Self, byteorder::BigEndian>(body),
            1 => cdr_encoding::from_bytes::<Self, byteorder::LittleEndian>(body),
            k => {
                let m = format!("CDR encapsulation {k} is not plain CDR");
                return Err(cdr_encoding::Error::Message(m));
            }
        };
        r.map(|(m, _)| m)
    }
}

/// The samples of one topic, as the messages give them.
#[derive(Default)]
struct Rows {
    log: RawLog,
    stamps_zero: bool,
    log_times: Vec<f64>,
    skipped: usize,
    /// Messages on the topic so far (the number errors give).
    seen: usize,
    qd: Samples,
    tau: Samples,
}

/// The longest MCAP record read (bytes), compressed or not: a record
/// header claiming more (a corrupt or hostile chunk) is an error before
/// anything is allocated for it.
pub const MAX_RECORD_BYTES: usize = 256 << 20;

/// A channel as its records declare it: topic, schema name, encoding.
struct ChannelInfo {
    topic: String,
    schema: String,
    encoding: String,
}

/// Calls `f(channel, log time (ns), data)` for every message of the bag
/// `bytes`, in file order (chunks decompressed, records longer than
/// [`MAX_RECORD_BYTES`] refused); `Err(Ok(message))` for a bag that cannot be
/// read, `Err(Err(e))` for `f`'s error.
fn for_each_message(
    bytes: &[u8],
    mut f: impl FnMut(&ChannelInfo, u64, &[u8]) -> Result<(), DataError>,
) -> Result<(), Result<String, DataError>> {
    use ::mcap::records::Record;
    use ::mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};
    use std::collections::HashMap;
    let opts = LinearReaderOptions::default()
        .with_record_length_limit(MAX_RECORD_BYTES)
        .with_prevalidate_chunk_crcs(true);
    let mut reader = LinearReader::new_with_options(opts);
    let (mut buf, mut schemas, mut channels) = (bytes, HashMap::new(), HashMap::new());
    let (mut records, corrupt) = (0usize, |e: String| Err(Ok(e)));
    while let Some(event) = reader.next_event() {
        match event.map_err(|e| Ok(format!("truncated or corrupt after record {records}: {e}")))? {
            LinearReadEvent::ReadRequest(need) => {
                let n = need.min(buf.len());
                reader.insert(n).copy_from_slice(&buf[..n]);
                reader.notify_read(n);
                buf = &buf[n..];
            }
            LinearReadEvent::Record { data, opcode } => {
                records += 1;
                match ::mcap::parse_record(opcode, data) {
                    Err(e) => return corrupt(format!("record {records}: {e}")),
                    Ok(Record::Schema { header, .. }) => {
                        schemas.insert(header.id, header.name);
                    }
                    Ok(Record::Channel(c)) => {
                        let schema = schemas.get(&c.schema_id).cloned().unwrap_or_default();
                        let info = ChannelInfo {
                            topic: c.topic,
                            schema,
                            encoding: c.message_encoding,
                        };
                        channels.insert(c.id, info);
                    }
                    Ok(Record::Message { header, data }) => {
                        let Some(c) = channels.get(&header.channel_id) else {
                            return corrupt(format!(
                                "record {records}: a message on channel {}, which no record declares",
                                header.channel_id
                            ));
                        };
                        f(c, header.log_time, &data).map_err(Err)?;
                    }
                    Ok(_) => {}
                }
            }
        }
    }
    Ok(())
}

/// Reads a bag's JointState messages for the robot's `joints`.
pub fn read_mcap(
    path: &Path,
    mapping: Option<&Mapping>,
    joints: &[&str],
) -> Result<RawLog, DataError> {
    let p = path.display().to_string();
    let bytes = read_bounded(path, &p)?;
    let topic = mapping.and_then(|m| m.topic.as_deref());
    let bad = |array: &str, message: String| DataError::Array {
        path: p.clone(),
        array: array.into(),
        message,
    };
    let mut topics: Vec<(String, String)> = vec![];
    let mut rows = Rows {
        stamps_zero: true,
        log: RawLog {
            q: Samples::new(joints.len()),
            ..RawLog::default()
        },
        qd: Samples::new(joints.len()),
        tau: Samples::new(joints.len()),
        ..Rows::default()
    };
    let mut chosen: Option<String> = None;
    let read = for_each_message(&bytes, |c, log_time, data| {
        let (name, schema) = (&c.topic, c.schema.as_str());
        if !topics.iter().any(|(t, _)| t == name) {
            topics.push((name.clone(), schema.to_string()));
        }
        let wanted = match topic {
            Some(t) => t == name,
            None => schema == JOINT_STATE,
        };
        if !wanted {
            return Ok(());
        }
        if schema != JOINT_STATE || c.encoding != "cdr" {
            return Err(bad(
                name,
                format!(
                    "the topic carries {schema:?} in {:?}, not {JOINT_STATE} in CDR",
                    c.encoding
                ),
            ));
        }
        match &chosen {
            Some(other) if other != name => {
                return Err(bad(
                    "(topic)",
                    format!(
                        "JointState on several topics ({other}, {name}, ...): name one with the mapping's `topic`"
                    ),
                ));
            }
            _ => chosen = Some(name.clone()),
        }
        rows.seen += 1;
        let msg = JointState::from_cdr(data).map_err(|e| {
            bad(
                name,
                format!("message {}: not a JointState: {e}", rows.seen),
            )
        })?;
        rows.push(msg, log_time, joints, &p, name)
    });
    match read {
        Ok(()) => {}
        Err(Ok(m)) => return Err(bad("(bag)", format!("not a readable MCAP file: {m}"))),
        Err(Err(e)) => return Err(e),
    }
    let Some(name) = chosen else {
        return Err(no_topic(&p, topic, &topics));
    };
    rows.finish(&p, &name)
}

/// The bag's bytes, refused beyond [`MAX_BAG_BYTES`].
fn read_bounded(path: &Path, p: &str) -> Result<Vec<u8>, DataError> {
    crate::io::read_capped(path, MAX_BAG_BYTES).map_err(|e| match e {
        crate::io::Capped::Io(source) => DataError::Io {
            path: p.into(),
            source,
        },
        crate::io::Capped::TooLarge(len) => DataError::Array {
            path: p.into(),
            array: "(bag)".into(),
            message: format!("{len} bytes; at most {MAX_BAG_BYTES} are read"),
        },
    })
}

/// The error for a bag without the (or any) JointState topic.
fn no_topic(p: &str, topic: Option<&str>, topics: &[(String, String)]) -> DataError {
    let listed = if topics.is_empty() {
        "the bag has no messages".to_string()
    } else {
        let t: Vec<String> = topics.iter().map(|(t, s)| format!("{t} ({s})")).collect();
        format!("its topics: {}", t.join(", "))
    };
    let (array, what) = match topic {
        Some(t) => (t.to_string(), "no messages on this topic"),
        None => ("(topic)".to_string(), "no sensor_msgs/msg/JointState topic"),
    };
    DataError::Array {
        path: p.into(),
        array,
        message: format!("{what}; {listed}"),
    }
}

impl Rows {
    /// Adds one message's row (or counts it skipped).
    fn push(
        &mut self,
        msg: JointState,
        log_time_ns: u64,
        joints: &[&str],
        p: &str,
        topic: &str,
    ) -> Result<(), DataError> {
        let row = self.log.len() + 1;
        let seen = self.seen;
        let bad = |message: String| DataError::Array {
            path: p.into(),
            array: topic.into(),
            message: format!("message {seen}: {message}"),
        };
        let at: Vec<Option<usize>> = (joints.iter())
            .map(|j| msg.name.iter().position(|n| n == j))
            .collect();
        if at.iter().all(Option::is_none) {
            self.skipped += 1;
            return Ok(());
        }
        if let Some(k) = at.iter().position(Option::is_none) {
            return Err(bad(format!(
                "joint '{}' missing (the message names {})",
                joints[k],
                msg.name.join(", ")
            )));
        }
        if self.log.len() >= MAX_ROWS {
            return Err(bad(format!("more than {MAX_ROWS} messages")));
        }
        let at: Vec<usize> = at.into_iter().flatten().collect();
        let n = msg.name.len();
        let pick = |v: &[f64], field: &str| -> Result<Option<Vec<f64>>, DataError> {
            match v.len() {
                0 if field != "position" => Ok(None),
                l if l == n => at
                    .iter()
                    .map(|&i| {
                        check_value(v[i], MAX_ABS_VALUE, p, &format!("{topic}.{field}"), seen)
                    })
                    .collect::<Result<_, _>>()
                    .map(Some),
                l => Err(bad(format!("{l} {field} values for {n} names"))),
            }
        };
        let q = pick(&msg.position, "position")?.expect("position is required");
        let qd = pick(&msg.velocity, "velocity")?;
        let tau = pick(&msg.effort, "effort")?;
        let s = msg.header.stamp;
        self.stamps_zero &= s.sec == 0 && s.nanosec == 0;
        self.log
            .t
            .push(f64::from(s.sec) + 1e-9 * f64::from(s.nanosec));
        self.log_times.push(1e-9 * log_time_ns as f64);
        self.log.q.push(&q);
        self.optional(qd, true, row, p, topic)?;
        self.optional(tau, false, row, p, topic)
    }

    /// Adds a row's velocities or efforts: every message has them or none.
    fn optional(
        &mut self,
        v: Option<Vec<f64>>,
        velocity: bool,
        row: usize,
        p: &str,
        topic: &str,
    ) -> Result<(), DataError> {
        let field = if velocity { "velocity" } else { "effort" };
        let rows = if velocity {
            &mut self.qd
        } else {
            &mut self.tau
        };
        match v {
            Some(v) if rows.len() + 1 == row => rows.push(&v),
            None if rows.is_empty() => {}
            _ => {
                return Err(DataError::Array {
                    path: p.into(),
                    array: format!("{topic}.{field}"),
                    message: format!("message {row}: some messages have it and others not"),
                });
            }
        }
        Ok(())
    }

    /// The log, with the warnings of what was skipped or substituted.
    fn finish(mut self, p: &str, topic: &str) -> Result<RawLog, DataError> {
        let n = self.log.len();
        if n == 0 {
            return Err(DataError::Array {
                path: p.into(),
                array: topic.into(),
                message: "no message names the robot's joints".into(),
            });
        }
        self.log.path = p.into();
        if self.stamps_zero && n > 1 {
            self.log.t = self.log_times;
            self.log.warnings.push(ReadWarning::LogTimesUsed {
                topic: topic.into(),
            });
        }
        if self.skipped > 0 {
            self.log.warnings.push(ReadWarning::MessagesSkipped {
                topic: topic.into(),
                count: self.skipped,
            });
        }
        let full = |v: Samples| (v.len() == n).then_some(v);
        self.log.qd = full(self.qd);
        self.log.tau = full(self.tau);
        Ok(self.log)
    }
}

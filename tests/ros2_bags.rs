//! ROS 2 bags in MCAP: `sensor_msgs/msg/JointState` messages that the
//! tests write (with the `mcap` crate), read like any other log; malformed
//! bags are errors naming the file and the topic. No test here needs
//! `../shared`.

use momentlmi::data::ros2::{Header, JOINT_STATE, JointState, Time};
use momentlmi::data::{Mapping, ReadOptions, read_logs};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

const J: [&str; 2] = ["a", "b"];

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("momentlmi-bags-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// q, q̇, q̈ of the motion: a = 0.8 sin(2π 0.4 t), b = 0.5 sin(2π 0.7 t).
fn motion(t: f64) -> [[f64; 2]; 3] {
    let w = [2.0 * PI * 0.4, 2.0 * PI * 0.7];
    let amp = [0.8, 0.5];
    let q = [amp[0] * (w[0] * t).sin(), amp[1] * (w[1] * t).sin()];
    let qd = [
        amp[0] * w[0] * (w[0] * t).cos(),
        amp[1] * w[1] * (w[1] * t).cos(),
    ];
    [q, qd, [-w[0] * w[0] * q[0], -w[1] * w[1] * q[1]]]
}

/// A state message at `t` (s) with the joints in the publisher's order
/// (b, gripper, a) and effort 3 q̈ + 1.
fn state(t: f64, stamp: bool) -> JointState {
    let [q, qd, qdd] = motion(t);
    let sec = t.floor();
    JointState {
        header: Header {
            stamp: if stamp {
                Time {
                    sec: sec as i32,
                    nanosec: ((t - sec) * 1e9).round() as u32,
                }
            } else {
                Time::default()
            },
            frame_id: String::new(),
        },
        name: vec!["b".into(), "gripper".into(), "a".into()],
        position: vec![q[1], 0.01, q[0]],
        velocity: vec![qd[1], 0.0, qd[0]],
        effort: vec![3.0 * qdd[1] + 1.0, 0.0, 3.0 * qdd[0] + 1.0],
    }
}

/// A message naming only a joint the robot lacks (another publisher).
fn gripper_only(t: f64) -> JointState {
    let mut m = state(t, true);
    m.name = vec!["gripper".into()];
    m.position = vec![0.01];
    m.velocity.clear();
    m.effort.clear();
    m
}

/// Writes a bag: `topics` (name, schema), then each message on its topic
/// (by index) at its log time (ns).
fn write_bag(path: &Path, topics: &[(&str, &str)], messages: &[(usize, u64, Vec<u8>)]) {
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut w = mcap::Writer::new(file).unwrap();
    let channels: Vec<u16> = topics
        .iter()
        .map(|(topic, schema)| {
            let s = w.add_schema(schema, "ros2msg", b"").unwrap();
            w.add_channel(s, topic, "cdr", &BTreeMap::new()).unwrap()
        })
        .collect();
    for (seq, (c, log_time, data)) in messages.iter().enumerate() {
        let header = mcap::records::MessageHeader {
            channel_id: channels[*c],
            sequence: seq as u32,
            log_time: *log_time,
            publish_time: *log_time,
        };
        w.write_to_known_channel(&header, data).unwrap();
    }
    w.finish().unwrap();
}

/// Stamps 4–6 ms apart from Unix time 1.7e9 s.
fn stamps(n: usize) -> Vec<f64> {
    let mut t = vec![1.7e9];
    for k in 1..n {
        t.push(t[k - 1] + 5e-3 + 1e-3 * (k as f64 * 0.9).sin());
    }
    t
}

/// A bag of the motion on /joint_states, with other traffic: /tf messages
/// and one gripper-only state every 50.
fn motion_bag(path: &Path, n: usize, stamp: bool) -> Vec<f64> {
    let t = stamps(n);
    let ns = |x: f64| (x * 1e9) as u64;
    let mut msgs = vec![];
    for (k, &x) in t.iter().enumerate() {
        msgs.push((0, ns(x), state(x, stamp).to_cdr().unwrap()));
        if k % 50 == 0 {
            msgs.push((0, ns(x) + 1000, gripper_only(x).to_cdr().unwrap()));
            msgs.push((1, ns(x), vec![0, 1, 0, 0, 1, 2, 3, 4]));
        }
    }
    let topics = [
        ("/joint_states", JOINT_STATE),
        ("/tf", "tf2_msgs/msg/TFMessage"),
    ];
    write_bag(path, &topics, &msgs);
    t
}

fn opts() -> ReadOptions {
    ReadOptions {
        cutoff_hz: Some(8.0),
        ..ReadOptions::default()
    }
}

/// The largest error of q̈ and of τ against the motion's (whose periods
/// divide the bag's start, 1.7e9 s: absolute or relative times alike).
fn errors(d: &momentlmi::data::Dataset) -> (f64, f64) {
    let (mut eq, mut et) = (0.0f64, 0.0f64);
    for k in 0..d.len() {
        let [_, _, qdd] = motion(d.t[k]);
        for j in 0..2 {
            eq = eq.max((d.qdd[k][j] - qdd[j]).abs());
            et = et.max((d.tau[k][j] - (3.0 * qdd[j] + 1.0)).abs());
        }
    }
    (eq, et)
}

#[test]
fn a_bag_of_joint_states_is_read_by_name_with_each_message_stamp() {
    let d = dir("read");
    let p = d.join("run.mcap");
    motion_bag(&p, 3000, true);
    let r = read_logs(&[&p], &J, &opts()).unwrap();
    let f = &r.files[0];
    // 3000 states read; the 60 gripper-only messages skipped, with a warning
    assert_eq!(f.rows, 3000);
    assert!(
        f.warnings
            .iter()
            .any(|w| w.to_string().contains("60 messages")),
        "{:?}",
        f.warnings
    );
    assert!((f.resampled_hz - 200.0).abs() < 5.0, "{}", f.resampled_hz);
    // joints matched by name (the publisher's order is b, gripper, a)
    let (eq, et) = errors(&r.data);
    assert!(eq < 0.05 && et < 0.15, "q̈ off by {eq}, τ by {et}");
}

#[test]
fn a_bag_with_unset_stamps_uses_log_times_and_says_so() {
    let d = dir("stamps");
    let p = d.join("run.mcap");
    motion_bag(&p, 1000, false);
    let r = read_logs(&[&p], &J, &opts()).unwrap();
    let w = &r.files[0].warnings;
    assert!(
        w.iter().any(|w| w.to_string().contains("log times")),
        "{w:?}"
    );
    let (eq, _) = errors(&r.data);
    assert!(eq < 0.05, "q̈ off by {eq}");
}

fn mapping_topic(topic: &str) -> ReadOptions {
    let m = Mapping::parse(&format!("topic = \"{topic}\""), "m.toml").unwrap();
    ReadOptions {
        mapping: Some(m),
        ..opts()
    }
}

#[test]
fn the_topic_is_the_only_joint_state_one_or_the_mapping_names_it() {
    let d = dir("topics");
    let p = d.join("two.mcap");
    let t = stamps(400);
    let mut msgs = vec![];
    for &x in &t {
        msgs.push((0, (x * 1e9) as u64, state(x, true).to_cdr().unwrap()));
        let mut slow = state(x, true);
        slow.position = slow.position.iter().map(|v| 0.5 * v).collect();
        msgs.push((1, (x * 1e9) as u64, slow.to_cdr().unwrap()));
    }
    let topics = [
        ("/left/joint_states", JOINT_STATE),
        ("/right/joint_states", JOINT_STATE),
    ];
    write_bag(&p, &topics, &msgs);
    let e = read_logs(&[&p], &J, &opts()).unwrap_err().to_string();
    assert!(
        e.contains("two.mcap") && e.contains("several topics"),
        "{e}"
    );
    let right = read_logs(&[&p], &J, &mapping_topic("/right/joint_states")).unwrap();
    let left = read_logs(&[&p], &J, &mapping_topic("/left/joint_states")).unwrap();
    let k = right.data.len() / 2;
    assert!((right.data.q[k][0] - 0.5 * left.data.q[k][0]).abs() < 1e-9);
    let e = (read_logs(&[&p], &J, &mapping_topic("/joint_state")).unwrap_err()).to_string();
    assert!(
        e.contains("two.mcap: /joint_state: no messages on this topic")
            && e.contains("/left/joint_states (sensor_msgs/msg/JointState)"),
        "{e}"
    );
}

/// Writes a one-topic bag of `m` (every message `m(k)`) and returns the
/// error reading it.
fn read_error(d: &Path, name: &str, m: impl Fn(usize) -> JointState) -> String {
    let p = d.join(name);
    let msgs: Vec<_> = (0..200)
        .map(|k| (0, 1_000_000 * k as u64, m(k).to_cdr().unwrap()))
        .collect();
    write_bag(&p, &[("/joint_states", JOINT_STATE)], &msgs);
    read_logs(&[&p], &J, &opts()).unwrap_err().to_string()
}

#[test]
fn malformed_bags_name_the_file_the_topic_and_the_message() {
    let d = dir("malformed");
    let at = |k: usize| state(1.0 + 5e-3 * k as f64, true);
    let e = read_error(&d, "nan.mcap", |k| {
        let mut m = at(k);
        if k == 7 {
            m.position[2] = f64::NAN;
        }
        m
    });
    assert!(
        e.contains("nan.mcap: /joint_states.position: row 8: non-finite"),
        "{e}"
    );
    let e = read_error(&d, "missing.mcap", |k| {
        let mut m = at(k);
        m.name[0] = "bb".into();
        m
    });
    assert!(
        e.contains("missing.mcap: /joint_states: message 1: joint 'b' missing"),
        "{e}"
    );
    let e = read_error(&d, "short.mcap", |k| {
        let mut m = at(k);
        m.effort.pop();
        m
    });
    assert!(e.contains("2 effort values for 3 names"), "{e}");
    let e = read_error(&d, "none.mcap", |k| gripper_only(k as f64));
    assert!(
        e.contains("none.mcap: /joint_states: no message names the robot's joints"),
        "{e}"
    );
    // no JointState at all
    let p = d.join("tf.mcap");
    write_bag(
        &p,
        &[("/tf", "tf2_msgs/msg/TFMessage")],
        &[(0, 1, vec![0, 1, 0, 0])],
    );
    let e = read_logs(&[&p], &J, &opts()).unwrap_err().to_string();
    assert!(
        e.contains("tf.mcap: (topic): no sensor_msgs/msg/JointState topic; its topics: /tf"),
        "{e}"
    );
    // a topic of another type, named by the mapping
    let e = read_logs(&[&p], &J, &mapping_topic("/tf"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("tf.mcap: /tf: the topic carries \"tf2_msgs/msg/TFMessage\""),
        "{e}"
    );
}

#[test]
fn truncated_and_corrupt_bags_are_errors_naming_the_file() {
    let d = dir("truncated");
    let p = d.join("whole.mcap");
    motion_bag(&p, 1000, true);
    let bytes = std::fs::read(&p).unwrap();
    for (name, cut) in [
        ("half.mcap", bytes.len() / 2),
        ("tiny.mcap", 5),
        ("empty.mcap", 0),
    ] {
        let q = d.join(name);
        std::fs::write(&q, &bytes[..cut]).unwrap();
        let e = read_logs(&[&q], &J, &opts()).unwrap_err().to_string();
        assert!(e.contains(name) && e.contains("(bag)"), "{e}");
    }
    // a message that is not CDR JointState
    let q = d.join("garbage.mcap");
    write_bag(
        &q,
        &[("/joint_states", JOINT_STATE)],
        &[(0, 1, vec![0, 1, 0, 0, 9])],
    );
    let e = read_logs(&[&q], &J, &opts()).unwrap_err().to_string();
    assert!(
        e.contains("garbage.mcap: /joint_states: message 1: not a JointState"),
        "{e}"
    );
}

/// Records whose headers claim more than a bag could hold (a hostile or
/// corrupt file) are errors, not allocations: a 1 TiB record, and a small
/// zstd chunk claiming 1 TiB once decompressed.
#[test]
fn records_claiming_huge_lengths_are_errors() {
    let d = dir("huge");
    let magic = b"\x89MCAP0\r\n";
    let mut header = vec![0x01];
    header.extend(10u64.to_le_bytes());
    header.extend(0u32.to_le_bytes()); // profile ""
    header.extend(2u32.to_le_bytes());
    header.extend(b"rs"); // library "rs"
    let mut huge = magic.to_vec();
    huge.extend([0x01]);
    huge.extend((1u64 << 40).to_le_bytes());
    huge.extend([0u8; 64]);
    let mut chunk = magic.to_vec();
    chunk.extend(&header);
    let body: Vec<u8> = [
        &0u64.to_le_bytes()[..],         // message start time
        &0u64.to_le_bytes()[..],         // message end time
        &(1u64 << 40).to_le_bytes()[..], // uncompressed size
        &0u32.to_le_bytes()[..],         // uncompressed crc
        &4u32.to_le_bytes()[..],
        b"zstd",
        &16u64.to_le_bytes()[..], // records
        &[0x28, 0xb5, 0x2f, 0xfd, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
    ]
    .concat();
    chunk.push(0x06);
    chunk.extend((body.len() as u64).to_le_bytes());
    chunk.extend(body);
    chunk.extend(magic);
    for (name, bytes) in [("huge.mcap", huge), ("chunk.mcap", chunk)] {
        let p = d.join(name);
        std::fs::write(&p, bytes).unwrap();
        let e = read_logs(&[&p], &J, &opts()).unwrap_err().to_string();
        assert!(e.contains(name) && e.contains("(bag)"), "{e}");
    }
}

#[test]
fn a_message_round_trips_through_cdr() {
    let m = state(1.25, true);
    let bytes = m.to_cdr().unwrap();
    assert_eq!(&bytes[..4], &[0, 1, 0, 0]);
    assert_eq!(JointState::from_cdr(&bytes).unwrap(), m);
    // ROS 2's layout: after the stamp (8 bytes), frame_id's length (4) and
    // its NUL (1, padded to 4), the names' count
    assert_eq!(u32::from_le_bytes(bytes[20..24].try_into().unwrap()), 3);
    assert!(JointState::from_cdr(&bytes[..3]).is_err());
}

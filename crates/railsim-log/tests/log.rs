//! Integration tests of railsim-log: round trips, counts and time ranges, metadata, a writer
//! killed with SIGKILL, determinism, CSV export and statistics, bad input.

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use railsim_log::export::{export_csv, export_csv_files, summarize};
use railsim_log::{
    BodyState, Creepages, FrameTransform, LogError, LogHeader, LogReader, LogWriter, PatchMessage,
    Quaternion, Query, Side, WheelsetMessage, WriterOptions, ns_to_s, step_time_ns, topics,
    wear_number,
};

fn temp_path(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("railsim_log_tests_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

const DT_NS: u64 = 1_000_000;

fn body(step: u64) -> BodyState {
    let t_s = ns_to_s(step * DT_NS);
    BodyState {
        t_s,
        name: "wheelset_0".into(),
        // Values that do not have short decimal forms, to exercise exact float round trips.
        position: [
            55.0 * t_s,
            1e-3 * (t_s * 7.0).sin() / 3.0,
            0.46 + f64::EPSILON * step as f64,
        ],
        orientation: Quaternion {
            x: 1e-300,
            y: -0.0,
            z: (0.1 + 0.2) / 3.0,
            w: 1.0 - 1e-16,
        },
        velocity: [55.0, 1.0 / 3.0, -5e-324],
        angular_velocity: [0.0, 119.56521739130434, std::f64::consts::PI * step as f64],
    }
}

fn patch(step: u64, side: Side, patch: u32) -> PatchMessage {
    let creepages = Creepages {
        xi: 1e-4 * (step as f64 + 1.0),
        eta: -2e-4 / 3.0,
        phi_per_m: 0.0123,
    };
    let (fx_n, fy_n) = (-2000.0 - step as f64, 4000.0 / 7.0);
    PatchMessage {
        t_s: ns_to_s(step * DT_NS),
        wheelset: 1,
        side,
        patch,
        y_rail_m: 0.0123 + patch as f64 * 1e-3,
        y_wheel_m: -0.004 / 3.0,
        contact_angle_rad: 0.0250001,
        penetration_m: 8.1234e-5,
        creepages,
        fn_n: 54_500.0 / 3.0,
        fx_n,
        fy_n,
        mz_nm: 1.5e-2,
        wear_number_n: wear_number(fx_n, fy_n, &creepages),
        weight: None,
    }
}

fn wheelset(step: u64) -> WheelsetMessage {
    WheelsetMessage {
        t_s: ns_to_s(step * DT_NS),
        wheelset: 1,
        y_left_n: 1000.0 + step as f64,
        q_left_n: 54_500.0,
        y_right_n: -1000.0 / 3.0,
        q_right_n: 54_000.0,
        y_over_q_left: (1000.0 + step as f64) / 54_500.0,
        y_over_q_right: -1000.0 / 3.0 / 54_000.0,
        angle_of_attack_rad: -1.25e-3,
        wear_number_left_n: 0.0,
        wear_number_right_n: 0.0,
        rail_displacement_m: Some([1e-5 * step as f64, -5.45e-4, -1e-5, -5.4e-4]),
    }
}

fn header() -> LogHeader {
    LogHeader::new()
        .scene_entry("vehicle", "manchester_1")
        .scene_entry("speed_m_s", "55")
        .scene_entry("note", "unicode ✓, = and \"quotes\"")
        .scene_toml("[scene]\nvehicle = \"manchester_1\"\nspeed_m_s = 55.0\n")
        .metadata(
            "integrator",
            BTreeMap::from([("method".to_owned(), "rk4".to_owned())]),
        )
}

/// Writes `steps` steps: per step one body, one /tf, two left patches, one right patch, one
/// wheelset message.
fn write_log(path: &Path, steps: u64, options: WriterOptions) -> railsim_log::LogStats {
    let mut log = LogWriter::create(path, &header(), options).unwrap();
    let b = log
        .channel::<BodyState>(&topics::body("wheelset_0"))
        .unwrap();
    let tf = log.channel::<FrameTransform>(topics::TF).unwrap();
    let left = log
        .channel::<PatchMessage>(&topics::contact(1, Side::Left))
        .unwrap();
    let right = log
        .channel::<PatchMessage>(&topics::contact(1, Side::Right))
        .unwrap();
    let ws = log
        .channel::<WheelsetMessage>(&topics::wheelset(1))
        .unwrap();
    for step in 0..steps {
        let t_ns = step_time_ns(step, DT_NS).unwrap();
        let state = body(step);
        log.write(&b, t_ns, &state).unwrap();
        log.write(&tf, t_ns, &FrameTransform::from_body(t_ns, "track", &state))
            .unwrap();
        log.write(&left, t_ns, &patch(step, Side::Left, 0)).unwrap();
        log.write(&left, t_ns, &patch(step, Side::Left, 1)).unwrap();
        log.write(&right, t_ns, &patch(step, Side::Right, 0))
            .unwrap();
        log.write(&ws, t_ns, &wheelset(step)).unwrap();
    }
    log.finish().unwrap()
}

#[test]
fn round_trip_of_all_message_types() {
    let path = temp_path("round_trip.mcap");
    write_log(
        &path,
        200,
        WriterOptions {
            chunk_size: 4096,
            ..WriterOptions::default()
        },
    );
    let reader = LogReader::open(&path).unwrap();
    assert!(reader.is_complete());
    assert!(reader.truncation().is_none());

    let bodies = reader
        .read_topic::<BodyState>("/bodies/wheelset_0", None)
        .unwrap();
    assert_eq!(bodies.len(), 200);
    for (step, (t_ns, b)) in bodies.iter().enumerate() {
        assert_eq!(*t_ns, step as u64 * DT_NS);
        // Bit-exact, including -0.0 and subnormals.
        let expected = body(step as u64);
        assert_eq!(b, &expected);
        assert_eq!(b.orientation.y.to_bits(), expected.orientation.y.to_bits());
        assert_eq!(b.velocity[2].to_bits(), expected.velocity[2].to_bits());
    }
    let tf = reader.read_topic::<FrameTransform>("/tf", None).unwrap();
    assert_eq!(tf.len(), 200);
    for (step, (t_ns, m)) in tf.iter().enumerate() {
        assert_eq!(
            m,
            &FrameTransform::from_body(*t_ns, "track", &body(step as u64))
        );
        assert_eq!(m.timestamp.to_ns(), *t_ns);
    }
    let left = reader
        .read_topic::<PatchMessage>("/contact/1/left", None)
        .unwrap();
    assert_eq!(left.len(), 400);
    for (i, (_, p)) in left.iter().enumerate() {
        assert_eq!(p, &patch(i as u64 / 2, Side::Left, (i % 2) as u32));
        assert!(
            p.wear_number_n > 0.0,
            "Tγ must be positive for forces opposing creepage"
        );
    }
    let right = reader
        .read_topic::<PatchMessage>("/contact/1/right", None)
        .unwrap();
    assert!(
        right
            .iter()
            .enumerate()
            .all(|(i, (_, p))| *p == patch(i as u64, Side::Right, 0))
    );
    let ws = reader
        .read_topic::<WheelsetMessage>("/wheelsets/1", None)
        .unwrap();
    assert!(
        ws.iter()
            .enumerate()
            .all(|(i, (_, w))| *w == wheelset(i as u64))
    );
    assert_eq!(ws.len(), 200);

    // Channel schemas: railsim types carry their units, /tf carries Foxglove's schema name.
    let tf_channel = reader.channel("/tf").unwrap();
    assert_eq!(tf_channel.schema_name, "foxglove.FrameTransform");
    assert_eq!(tf_channel.schema_encoding, "jsonschema");
    assert_eq!(tf_channel.message_encoding, "json");
    let body_schema =
        String::from_utf8(reader.channel("/bodies/wheelset_0").unwrap().schema.clone()).unwrap();
    assert!(body_schema.contains("[m/s]"), "{body_schema}");
}

#[test]
fn counts_and_time_ranges() {
    let path = temp_path("counts.mcap");
    let stats = write_log(
        &path,
        1000,
        WriterOptions {
            flush_every: 333,
            ..WriterOptions::default()
        },
    );
    assert_eq!(stats.messages, 6000);
    assert_eq!((stats.start_ns, stats.end_ns), (0, 999 * DT_NS));
    assert!(stats.flushes >= 18, "flushes {}", stats.flushes);
    assert!(stats.chunks >= 18, "chunks {}", stats.chunks);
    let reader = LogReader::open(&path).unwrap();
    let counts: Vec<(&str, u64)> = reader
        .channels()
        .iter()
        .map(|c| (c.topic.as_str(), c.message_count))
        .collect();
    assert_eq!(
        counts,
        [
            ("/bodies/wheelset_0", 1000),
            ("/contact/1/left", 2000),
            ("/contact/1/right", 1000),
            ("/tf", 1000),
            ("/wheelsets/1", 1000)
        ]
    );
    for c in reader.channels() {
        assert_eq!(
            (c.first_ns, c.last_ns),
            (Some(0), Some(999 * DT_NS)),
            "{}",
            c.topic
        );
    }
    assert_eq!(reader.time_range(), Some((0, 999 * DT_NS)));
    assert_eq!(reader.message_count(), 6000);

    // Inclusive time range through the index: steps 100..=199.
    let range = Some((100 * DT_NS, 199 * DT_NS));
    let some = reader
        .read_topic::<PatchMessage>("/contact/1/left", range)
        .unwrap();
    assert_eq!(some.len(), 200);
    assert_eq!(some.first().unwrap().0, 100 * DT_NS);
    assert_eq!(some.last().unwrap().0, 199 * DT_NS);
    // Several topics, in log-time order, sequence numbers per channel.
    let mut seen = Vec::new();
    reader
        .for_each(
            &Query::topics(["/tf", "/wheelsets/1"]).between(10 * DT_NS, 12 * DT_NS),
            |m| {
                assert_eq!(m.log_time_ns, m.publish_time_ns);
                assert_eq!(u64::from(m.sequence) * DT_NS, m.log_time_ns);
                seen.push((m.channel.topic.clone(), m.log_time_ns));
                Ok(())
            },
        )
        .unwrap();
    assert_eq!(seen.len(), 6);
    assert!(seen.windows(2).all(|w| w[0].1 <= w[1].1));

    // Step times come from integers: no drift after many steps.
    assert_eq!(step_time_ns(3_600_000, 250_000).unwrap(), 900_000_000_000);
    assert!(matches!(
        step_time_ns(u64::MAX, 2),
        Err(LogError::TimeOverflow { .. })
    ));
}

#[test]
fn metadata_round_trip() {
    let path = temp_path("metadata.mcap");
    write_log(&path, 3, WriterOptions::default());
    let reader = LogReader::open(&path).unwrap();
    let scene = reader.scene().unwrap();
    assert_eq!(scene, &header().scene);
    assert_eq!(reader.metadata()["integrator"]["method"], "rk4");
    assert_eq!(reader.metadata()["railsim_log"]["format_version"], "2");
    assert_eq!(reader.scene_toml().unwrap(), header().scene_toml.as_deref());
    let (media, _) = reader.attachment("scene.toml").unwrap();
    assert_eq!(media, "application/toml");

    // The metadata comes before the first chunk (Foxglove and `mcap doctor` expect no empty
    // chunk in front): the first chunk opcode (0x06) follows the metadata (0x0C) and attachment
    // (0x09) records in the file.
    let bytes = std::fs::read(&path).unwrap();
    let mut pos = 8;
    let mut ops = Vec::new();
    while pos + 9 <= bytes.len() && ops.len() < 6 {
        let op = bytes[pos];
        let len = u64::from_le_bytes(bytes[pos + 1..pos + 9].try_into().unwrap()) as usize;
        ops.push(op);
        pos += 9 + len;
    }
    assert_eq!(
        ops[..5],
        [0x01, 0x0C, 0x0C, 0x0C, 0x09],
        "records {ops:02x?}"
    );
    assert_eq!(ops[5], 0x06);

    // Reserved metadata names are refused.
    let bad = LogHeader::new().metadata("scene", BTreeMap::new());
    let err =
        LogWriter::create(temp_path("reserved.mcap"), &bad, WriterOptions::default()).unwrap_err();
    assert!(err.to_string().contains("reserved"), "{err}");
}

#[test]
fn two_writes_of_the_same_data_are_identical_bytes() {
    let a = temp_path("det_a.mcap");
    let b = temp_path("det_b.mcap");
    let options = WriterOptions {
        chunk_size: 16 * 1024,
        flush_every: 100,
        zstd: true,
    };
    write_log(&a, 500, options.clone());
    write_log(&b, 500, options);
    let (a, b) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    assert!(a.len() > 10_000);
    assert!(a == b, "two logs of the same data differ");
}

/// A topic whose messages carry a field only at times (a patch's `weight`, written only while
/// its wheel is in a rail transition) exports with the field's column and empty cells where
/// it is missing: the export before stop 39 stopped at the first message with a new field.
#[test]
fn csv_export_of_a_field_present_only_at_times() {
    let path = temp_path("csv_weight.mcap");
    let mut log = LogWriter::create(&path, &header(), WriterOptions::default()).unwrap();
    let left = log
        .channel::<PatchMessage>(&topics::contact(1, Side::Left))
        .unwrap();
    for step in 0..6u64 {
        let mut p = patch(step, Side::Left, 0);
        if (2..4).contains(&step) {
            p.weight = Some(0.25 * step as f64);
        }
        log.write(&left, step_time_ns(step, DT_NS).unwrap(), &p)
            .unwrap();
    }
    log.finish().unwrap();
    let reader = LogReader::open(&path).unwrap();
    let mut out = Vec::new();
    let export = export_csv(&reader, "/contact/1/left", None, &mut out).unwrap();
    assert_eq!(export.rows, 6);
    let text = String::from_utf8(out).unwrap();
    let lines: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    let k = lines[0]
        .iter()
        .position(|c| c.starts_with("weight"))
        .unwrap_or_else(|| panic!("no weight column: {:?}", lines[0]));
    assert_eq!(
        lines[0].iter().filter(|c| c.starts_with("weight")).count(),
        1
    );
    for (step, row) in lines[1..].iter().enumerate() {
        assert_eq!(row.len(), lines[0].len(), "row {step}: {row:?}");
        let want = if (2..4).contains(&step) {
            format!("{}", 0.25 * step as f64)
        } else {
            String::new()
        };
        assert_eq!(row[k], want, "row {step}");
        // the other columns keep their values
        assert_eq!(
            row[0],
            step_time_ns(step as u64, DT_NS).unwrap().to_string()
        );
    }
}

#[test]
fn csv_export_columns_values_and_statistics() {
    let path = temp_path("csv.mcap");
    write_log(&path, 50, WriterOptions::default());
    let reader = LogReader::open(&path).unwrap();

    let mut out = Vec::new();
    let export = export_csv(
        &reader,
        "/bodies/wheelset_0",
        Some((10 * DT_NS, 19 * DT_NS)),
        &mut out,
    )
    .unwrap();
    assert_eq!(export.rows, 10);
    let text = String::from_utf8(out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 11);
    assert_eq!(
        lines[0],
        "log_time_ns,t_s [s],name,position.0 [m],position.1 [m],position.2 [m],\
         orientation.x [1],orientation.y [1],orientation.z [1],orientation.w [1],\
         velocity.0 [m/s],velocity.1 [m/s],velocity.2 [m/s],\
         angular_velocity.0 [rad/s],angular_velocity.1 [rad/s],angular_velocity.2 [rad/s]"
    );
    assert_eq!(export.columns.join(","), lines[0]);
    let row: Vec<&str> = lines[1].split(',').collect();
    let expected = body(10);
    assert_eq!(row[0], "10000000");
    assert_eq!(row[2], "wheelset_0");
    assert_eq!(row[4].parse::<f64>().unwrap(), expected.position[1]);
    assert_eq!(
        row[11].parse::<f64>().unwrap().to_bits(),
        expected.velocity[1].to_bits()
    );

    let mut out = Vec::new();
    export_csv(&reader, "/contact/1/left", None, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let head = text.lines().next().unwrap();
    assert!(
        head.contains("creepages.phi_per_m [1/m]")
            && head.contains("mz_nm [N m]")
            && head.contains("side,patch"),
        "{head}"
    );
    assert_eq!(text.lines().count(), 101);

    let mut out = Vec::new();
    export_csv(&reader, "/tf", None, &mut out).unwrap();
    let head = String::from_utf8(out)
        .unwrap()
        .lines()
        .next()
        .unwrap()
        .to_owned();
    assert_eq!(
        head,
        "log_time_ns,timestamp.sec [s],timestamp.nsec [ns],parent_frame_id,child_frame_id,\
         translation.x [m],translation.y [m],translation.z [m],rotation.x [1],rotation.y [1],rotation.z [1],rotation.w [1]"
    );

    // One file per topic.
    let dir = temp_path("csv_dir");
    std::fs::create_dir_all(&dir).unwrap();
    let files = export_csv_files(&reader, &Query::all().between(0, 4 * DT_NS), &dir).unwrap();
    assert_eq!(files.len(), 5);
    let wheelsets = files.iter().find(|(t, _, _)| t == "/wheelsets/1").unwrap();
    assert_eq!(wheelsets.1.file_name().unwrap(), "wheelsets_1.csv");
    assert_eq!(wheelsets.2, 5);
    assert_eq!(
        std::fs::read_to_string(&wheelsets.1)
            .unwrap()
            .lines()
            .count(),
        6
    );

    // Statistics per numeric field.
    let stats = summarize(&reader, &Query::topics(["/wheelsets/1"])).unwrap();
    assert_eq!(stats.len(), 1);
    assert_eq!(stats[0].messages, 50);
    let y_left = stats[0]
        .fields
        .iter()
        .find(|f| f.path == "y_left_n")
        .unwrap();
    assert_eq!(y_left.unit.as_deref(), Some("N"));
    assert_eq!((y_left.min, y_left.max, y_left.count), (1000.0, 1049.0, 50));
    assert!((y_left.mean - 1024.5).abs() < 1e-9, "{}", y_left.mean);
    let ws_field = stats[0]
        .fields
        .iter()
        .find(|f| f.path == "wheelset")
        .unwrap();
    assert_eq!((ws_field.min, ws_field.max), (1.0, 1.0));
    let all = summarize(&reader, &Query::all()).unwrap();
    assert_eq!(all.len(), 5);
    assert_eq!(all.iter().map(|t| t.messages).sum::<u64>(), 300);
}

#[test]
fn bad_input_gives_errors_naming_the_file() {
    // Not an MCAP file.
    let path = temp_path("not_mcap.mcap");
    std::fs::write(&path, b"name = \"scene\"\n").unwrap();
    let err = LogReader::open(&path).unwrap_err().to_string();
    assert!(
        err.contains("not_mcap.mcap") && err.contains("expected the MCAP magic"),
        "{err}"
    );
    // Empty and missing files.
    let empty = temp_path("empty.mcap");
    std::fs::write(&empty, b"").unwrap();
    assert!(
        LogReader::open(&empty)
            .unwrap_err()
            .to_string()
            .contains("empty.mcap")
    );
    let missing = temp_path("missing.mcap");
    let err = LogReader::open(&missing).unwrap_err();
    assert!(
        matches!(err, LogError::Io { .. }) && err.to_string().contains("missing.mcap"),
        "{err}"
    );

    // A finished log with a flipped byte inside a chunk: the CRC check catches it.
    let good = temp_path("good.mcap");
    write_log(
        &good,
        300,
        WriterOptions {
            zstd: false,
            ..WriterOptions::default()
        },
    );
    let mut bytes = std::fs::read(&good).unwrap();
    let at = bytes.windows(10).position(|w| w == b"wheelset_0").unwrap() + 2;
    let at = at
        + bytes[at..]
            .windows(9)
            .position(|w| w == b"\"t_s\":0.1")
            .unwrap()
        + 7;
    bytes[at] = b'9';
    let bad = temp_path("flipped.mcap");
    std::fs::write(&bad, &bytes).unwrap();
    let err = LogReader::open(&bad).unwrap_err().to_string();
    assert!(err.contains("flipped.mcap"), "{err}");

    // Wrong types and unknown topics.
    let reader = LogReader::open(&good).unwrap();
    let err = reader
        .read_topic::<BodyState>("/tf", None)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("foxglove.FrameTransform") && err.contains("railsim.BodyState"),
        "{err}"
    );
    let err = reader
        .read_topic::<BodyState>("/bodies/nope", None)
        .unwrap_err()
        .to_string();
    assert!(err.contains("/bodies/nope"), "{err}");

    // Time may not go backwards; a topic keeps its type.
    let path = temp_path("backwards.mcap");
    let mut log = LogWriter::create(&path, &LogHeader::new(), WriterOptions::default()).unwrap();
    log.write_topic("/wheelsets/0", 5, &wheelset(0)).unwrap();
    let err = log
        .write_topic("/wheelsets/0", 4, &wheelset(0))
        .unwrap_err();
    assert!(
        matches!(
            err,
            LogError::TimeWentBackwards {
                t_ns: 4,
                previous_ns: 5,
                ..
            }
        ),
        "{err}"
    );
    assert!(log.write_topic("/wheelsets/0", 5, &body(0)).is_err());
    log.finish().unwrap();
}

/// A 120-step log in small (2 kB) compressed chunks at `name`, and its bytes.
fn small_chunk_log(name: &str) -> (PathBuf, Vec<u8>) {
    let path = temp_path(name);
    write_log(
        &path,
        120,
        WriterOptions {
            chunk_size: 2048,
            flush_every: 25,
            zstd: true,
        },
    );
    let bytes = std::fs::read(&path).unwrap();
    (path, bytes)
}

#[test]
fn truncated_at_any_byte_reads_a_prefix_or_fails_cleanly() {
    let (path, bytes) = small_chunk_log("cut_source.mcap");
    let full = LogReader::open(&path).unwrap();
    let all: Vec<(u64, WheelsetMessage)> = full.read_topic("/wheelsets/1", None).unwrap();
    let cut = temp_path("cut.mcap");
    let mut readable = 0;
    for len in (0..bytes.len())
        .step_by(97)
        .chain([bytes.len() - 1, bytes.len() - 8])
    {
        std::fs::write(&cut, &bytes[..len]).unwrap();
        let Ok(reader) = LogReader::open(&cut) else {
            continue;
        };
        readable += 1;
        assert!(!reader.is_complete());
        let Some(c) = reader.channel("/wheelsets/1") else {
            continue;
        };
        let got: Vec<(u64, WheelsetMessage)> = reader.read_topic(&c.topic, None).unwrap();
        assert_eq!(got.len() as u64, c.message_count);
        assert_eq!(got[..], all[..got.len()], "cut at {len}: not a prefix");
    }
    assert!(
        readable > bytes.len() / 97 / 2,
        "only {readable} cuts were readable"
    );
}

/// A file shorter than the header a railsim log starts with (MCAP magic and header and the
/// `railsim_log` metadata record, flushed when the log is created) is an error naming the file
/// and its size; so is a finished log whose footer puts the summary beyond the footer. Before,
/// a file of 8 to 36 bytes and a summary start beyond 2^63 gave `seeking the summary: Invalid
/// argument (os error 22)`, and a file of 37 bytes or more opened as an empty truncated log.
#[test]
fn short_files_and_damaged_footers_fail_naming_the_file_and_its_size() {
    let (_, bytes) = small_chunk_log("short_source.mcap");
    let cut = temp_path("short.mcap");
    let mut first_readable = None;
    for len in 0..bytes.len() {
        std::fs::write(&cut, &bytes[..len]).unwrap();
        match LogReader::open(&cut) {
            Ok(reader) => {
                // the first readable cut holds the whole railsim_log record, and is truncated
                assert!(
                    reader.metadata().contains_key("railsim_log"),
                    "cut at {len}"
                );
                assert!(reader.truncation().is_some(), "cut at {len}");
                first_readable = Some(len);
                break;
            }
            Err(e) => {
                let message = e.to_string();
                assert!(matches!(e, LogError::Corrupt { .. }), "cut at {len}: {e:?}");
                assert!(
                    message.contains("short.mcap: not a complete railsim log")
                        && message.contains(&format!("the file is {len} bytes long"))
                        && message.contains("expected at least the MCAP magic")
                        && !message.contains("os error"),
                    "cut at {len}: {message}"
                );
            }
        }
    }
    // past the magic (8), the MCAP header and the railsim_log record's three entries
    let first_readable = first_readable.expect("no cut was readable");
    assert!(
        first_readable > 100,
        "a cut at {first_readable} bytes opens"
    );

    let footer = bytes.len() - 37;
    assert_eq!(bytes[footer], 0x02, "no footer record at {footer}");
    let damaged = temp_path("bad_footer.mcap");
    for summary_start in [u64::MAX, 1 << 63, bytes.len() as u64, footer as u64] {
        let mut b = bytes.clone();
        b[footer + 9..footer + 17].copy_from_slice(&summary_start.to_le_bytes());
        std::fs::write(&damaged, &b).unwrap();
        let Err(e) = LogReader::open(&damaged) else {
            panic!("a footer putting the summary at byte {summary_start} opens");
        };
        let message = e.to_string();
        assert!(matches!(e, LogError::Corrupt { .. }), "{e:?}");
        assert!(
            message.contains("bad_footer.mcap: not a complete MCAP file: its footer is damaged")
                && message.contains(&format!("the file is {} bytes long", bytes.len()))
                && message.contains(&format!("at byte {footer}"))
                && message.contains(&format!("puts the summary at byte {summary_start}"))
                && !message.contains("os error"),
            "{message}"
        );
    }
}

/// Randomly damaged logs (bytes overwritten, a range deleted, random bytes inserted): opening and
/// reading every topic gives data or an error, never a panic or an allocation abort. Before, a
/// damaged record length made the reader ask for (and allocate) up to exabytes: 30 of 300
/// damaged copies of a `railsim run` log aborted `railsim replay`.
#[test]
fn damaged_logs_read_or_fail_cleanly() {
    let (_, bytes) = small_chunk_log("damage_source.mcap");
    let damaged = temp_path("damaged.mcap");
    let mut x: u64 = 5;
    let mut rnd = |n: usize| {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((x >> 33) as usize) % n.max(1)
    };
    let (mut opened, mut failed) = (0, 0);
    for k in 0..300 {
        let mut b = bytes.clone();
        match k % 3 {
            0 => {
                for _ in 0..1 + rnd(8) {
                    let i = rnd(b.len());
                    b[i] = rnd(256) as u8;
                }
            }
            1 => {
                let i = rnd(b.len());
                let j = (i + 1 + rnd(4000)).min(b.len());
                b.drain(i..j);
            }
            _ => {
                let i = rnd(b.len());
                let junk: Vec<u8> = (0..1 + rnd(64)).map(|_| rnd(256) as u8).collect();
                b.splice(i..i, junk);
            }
        }
        std::fs::write(&damaged, &b).unwrap();
        let Ok(reader) = LogReader::open(&damaged) else {
            failed += 1;
            continue;
        };
        opened += 1;
        for c in reader.channels().to_vec() {
            // data or an error naming the file
            if let Err(e) = reader.read_topic::<WheelsetMessage>(&c.topic, None) {
                assert!(e.to_string().contains("damaged.mcap"), "{e}");
            }
        }
    }
    // both outcomes, each in at least a tenth of the copies (how many open depends on how much
    // of the file is schema and index, which the reader refuses when damaged)
    assert!(
        opened >= 30 && failed >= 30,
        "{opened} opened, {failed} failed"
    );
}

/// Child side of the SIGKILL test: writes forever when `RAILSIM_LOG_CHILD` names a path.
#[test]
fn child_write_forever() {
    let Some(path) = std::env::var_os("RAILSIM_LOG_CHILD") else {
        return;
    };
    let options = WriterOptions {
        chunk_size: 1 << 20,
        flush_every: 0,
        zstd: true,
    };
    let mut log = LogWriter::create(&path, &header(), options).unwrap();
    let ws = log.channel::<WheelsetMessage>("/wheelsets/1").unwrap();
    let mut step = 0u64;
    loop {
        log.write(&ws, step * DT_NS, &wheelset(step)).unwrap();
        step += 1;
        if step.is_multiple_of(50) {
            log.flush().unwrap();
            println!("FLUSHED {step}");
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
    }
}

#[test]
fn sigkill_leaves_a_log_readable_up_to_the_last_flush() {
    let path = temp_path("killed.mcap");
    let mut child = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "child_write_forever",
            "--nocapture",
            "--test-threads=1",
        ])
        .env("RAILSIM_LOG_CHILD", &path)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let mut flushed = 0u64;
    while flushed < 20 * 50 {
        let line = lines.next().expect("child ended early").unwrap();
        if let Some(n) = line.strip_prefix("FLUSHED ") {
            flushed = n.parse().unwrap();
        }
    }
    // SIGKILL: no destructor, no summary.
    child.kill().unwrap();
    child.wait().unwrap();
    for line in lines {
        if let Some(n) = line.unwrap().strip_prefix("FLUSHED ") {
            flushed = n.parse().unwrap();
        }
    }

    let reader = LogReader::open(&path).unwrap();
    assert!(!reader.is_complete());
    assert!(reader.truncation().is_some());
    assert_eq!(reader.scene(), Some(&header().scene));
    let got: Vec<(u64, WheelsetMessage)> = reader.read_topic("/wheelsets/1", None).unwrap();
    let n = got.len() as u64;
    assert!(
        n >= flushed,
        "recovered {n} messages, but {flushed} were flushed"
    );
    assert_eq!(n % 50, 0, "recovered {n}: chunks end only at flushes");
    for (step, (t_ns, m)) in got.iter().enumerate() {
        assert_eq!(*t_ns, step as u64 * DT_NS);
        assert_eq!(m, &wheelset(step as u64), "message {step} differs");
    }
    assert_eq!(reader.channel("/wheelsets/1").unwrap().message_count, n);
}

/// A wheelset message of a log written before the wear numbers were added still reads (as 0);
/// an unknown field is still rejected.
#[test]
fn wheelset_messages_without_wear_numbers_read_as_zero() {
    let old = r#"{"t_s":0.5,"wheelset":1,"y_left_n":1.0,"q_left_n":2.0,"y_right_n":3.0,
        "q_right_n":4.0,"y_over_q_left":0.5,"y_over_q_right":0.75,"angle_of_attack_rad":0.001}"#;
    let m: WheelsetMessage = serde_json::from_str(old).unwrap();
    assert_eq!((m.wear_number_left_n, m.wear_number_right_n), (0.0, 0.0));
    assert_eq!(m.q_right_n, 4.0);
    let bad = old.replace("\"t_s\"", "\"bogus\":1,\"t_s\"");
    assert!(serde_json::from_str::<WheelsetMessage>(&bad).is_err());
}

/// A footer in place (opcode and closing magic) whose summary start is damaged but points inside
/// the file is not read as a killed run: the data are read on their own and the note names the
/// footer, where it puts the summary and the reader's error. A footer recording no summary
/// (start 0, allowed by MCAP) is a finished file without one. Before, both read as "the writer
/// stopped before finishing".
#[test]
fn a_footer_pointing_at_no_summary_is_reported_as_damaged_not_as_a_killed_run() {
    let (path, bytes) = small_chunk_log("footer_source.mcap");
    let whole = LogReader::open(&path).unwrap();
    let all: Vec<(u64, WheelsetMessage)> = whole.read_topic("/wheelsets/1", None).unwrap();
    let footer = bytes.len() - 37;
    let start = u64::from_le_bytes(bytes[footer + 9..footer + 17].try_into().unwrap());
    let damaged = temp_path("footer_inside.mcap");
    for summary_start in [100, start - 10, start + 3, footer as u64 - 5] {
        let mut b = bytes.clone();
        b[footer + 9..footer + 17].copy_from_slice(&summary_start.to_le_bytes());
        std::fs::write(&damaged, &b).unwrap();
        let reader = LogReader::open(&damaged).unwrap();
        assert!(!reader.is_complete());
        let note = reader.truncation().expect("a note");
        assert!(
            note.contains(&format!("footer (at byte {footer}) is in place"))
                && note.contains(&format!("puts the summary at byte {summary_start}"))
                && note.contains("the footer or the summary is damaged")
                && !note.contains("writer stopped"),
            "{summary_start}: {note}"
        );
        let read: Vec<(u64, WheelsetMessage)> = reader.read_topic("/wheelsets/1", None).unwrap();
        assert_eq!(read.len(), all.len(), "{summary_start}");
    }
    let mut b = bytes.clone();
    b[footer + 9..footer + 17].copy_from_slice(&0u64.to_le_bytes());
    std::fs::write(&damaged, &b).unwrap();
    let reader = LogReader::open(&damaged).unwrap();
    assert!(reader.is_complete() && reader.truncation().is_none());
    let read: Vec<(u64, WheelsetMessage)> = reader.read_topic("/wheelsets/1", None).unwrap();
    assert_eq!(read.len(), all.len());
}

/// The format version: a log of version 1 (before stop 26) is read, one of a later version than
/// this reader knows is refused naming the version (its fields may mean other things; a patched
/// "9" was read as a normal log).
#[test]
fn a_log_of_a_later_format_is_refused() {
    let path = temp_path("version.mcap");
    write_log(&path, 3, WriterOptions::default());
    let bytes = std::fs::read(&path).unwrap();
    let key = b"format_version\x01\x00\x00\x002";
    let at = bytes
        .windows(key.len())
        .position(|w| w == key)
        .expect("the version in the metadata");
    for (v, ok) in [(b'1', true), (b'2', true), (b'9', false)] {
        let mut patched = bytes.clone();
        patched[at + key.len() - 1] = v;
        let p = temp_path(&format!("version_{}.mcap", v as char));
        std::fs::write(&p, &patched).unwrap();
        match LogReader::open(&p) {
            Ok(r) => {
                assert!(ok, "version {} read", v as char);
                assert_eq!(
                    r.metadata()["railsim_log"]["format_version"],
                    (v as char).to_string()
                );
            }
            Err(e) => {
                assert!(!ok, "version {}: {e}", v as char);
                assert!(e.to_string().contains("log format version \"9\""), "{e}");
            }
        }
    }
}

//! `railsim replay`: listing, CSV export, PNG plots, truncated logs and bad input, on a log
//! written here with `railsim_log`'s own writer.

use crate::common;
use common::railsim;

use std::path::{Path, PathBuf};

use railsim_log::{
    BodyState, Creepages, LogHeader, LogWriter, PatchMessage, Quaternion, Side, WheelsetMessage,
    WriterOptions, ns_to_s, step_time_ns,
};

/// Steps of 1 ms in the test log.
const STEPS: u64 = 400;

fn temp_dir(name: &str) -> PathBuf {
    common::temp_dir("replay", name)
}

/// Per step: `/bodies/wheelset_0` (1), `/contact/0/left` (2 patches), `/wheelsets/0` (1).
fn write_log(path: &Path, options: WriterOptions) {
    let header = LogHeader::new()
        .scene_entry("name", "replay-test")
        .scene_entry("speed_m_s", "55");
    let mut log = LogWriter::create(path, &header, options).unwrap();
    let body = log.channel::<BodyState>("/bodies/wheelset_0").unwrap();
    let left = log.channel::<PatchMessage>("/contact/0/left").unwrap();
    let wheelset = log.channel::<WheelsetMessage>("/wheelsets/0").unwrap();
    for step in 0..STEPS {
        let t_ns = step_time_ns(step, 1_000_000).unwrap();
        let t_s = ns_to_s(t_ns);
        let y = 1e-3 * (2.0 * std::f64::consts::PI * 2.5 * t_s).sin();
        let state = BodyState {
            t_s,
            name: "wheelset_0".into(),
            position: [55.0 * t_s, y, 0.46],
            orientation: Quaternion::IDENTITY,
            velocity: [55.0, 0.0, 0.0],
            angular_velocity: [0.0, 55.0 / 0.46, 0.0],
        };
        log.write(&body, t_ns, &state).unwrap();
        for patch in 0..2u32 {
            let message = PatchMessage {
                t_s,
                wheelset: 0,
                side: Side::Left,
                patch,
                y_rail_m: y,
                y_wheel_m: y,
                contact_angle_rad: 0.03 + 0.5 * patch as f64,
                penetration_m: 8e-5,
                creepages: Creepages {
                    xi: 1e-4,
                    eta: -2e-4,
                    phi_per_m: 0.01,
                },
                fn_n: 20_000.0 + 10_000.0 * patch as f64,
                fx_n: -1000.0,
                fy_n: 3000.0 + y * 1e6,
                mz_nm: 1.0,
                wear_number_n: 0.5,
                weight: None,
            };
            log.write(&left, t_ns, &message).unwrap();
        }
        let q = 50_000.0;
        let message = WheelsetMessage {
            t_s,
            wheelset: 0,
            y_left_n: 2000.0 + y * 1e6,
            q_left_n: q,
            y_right_n: -2000.0,
            q_right_n: q,
            y_over_q_left: (2000.0 + y * 1e6) / q,
            y_over_q_right: -2000.0 / q,
            angle_of_attack_rad: 0.0,
            wear_number_left_n: 0.0,
            wear_number_right_n: 0.0,
            rail_displacement_m: None,
        };
        log.write(&wheelset, t_ns, &message).unwrap();
    }
    log.finish().unwrap();
}

fn sample_log(dir: &Path) -> PathBuf {
    let path = dir.join("run.mcap");
    write_log(&path, WriterOptions::default());
    path
}

#[test]
fn lists_channels_scene_and_statistics() {
    let dir = temp_dir("list");
    let log = sample_log(&dir);
    let (code, out, err) = railsim(&["replay", log.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("(finished)"), "{out}");
    assert!(out.contains("scene replay-test: 2 keys"), "{out}");
    assert!(out.contains("speed_m_s = 55"), "{out}");
    let row = |topic: &str| {
        out.lines()
            .find(|l| l.trim_start().starts_with(topic) && l.contains("railsim."))
            .unwrap_or_else(|| panic!("no channel row for {topic}:\n{out}"))
            .split_whitespace()
            .map(str::to_owned)
            .collect::<Vec<_>>()
    };
    assert_eq!(
        row("/wheelsets/0"),
        [
            "/wheelsets/0",
            "railsim.WheelsetMessage",
            "400",
            "0.000000",
            "0.399000"
        ]
    );
    assert_eq!(row("/contact/0/left")[2], "800");
    assert_eq!(row("/bodies/wheelset_0")[2], "400");
    // Statistics: Q is constant, units come from the schema.
    let q = out
        .lines()
        .find(|l| l.trim_start().starts_with("q_left_n"))
        .unwrap();
    assert_eq!(
        q.split_whitespace().collect::<Vec<_>>(),
        ["q_left_n", "N", "50000", "50000", "50000"]
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn exports_topics_and_a_time_range_to_csv() {
    let dir = temp_dir("csv");
    let log = sample_log(&dir);
    let out_dir = dir.join("csv");
    let (code, out, err) = railsim(&[
        "replay",
        log.to_str().unwrap(),
        "--topics",
        "/wheelsets/0,/contact/0/left",
        "--from-s",
        "0.1",
        "--to-s",
        "0.2",
        "--csv",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("/wheelsets/0: 101 rows"), "{out}");
    let text = std::fs::read_to_string(out_dir.join("wheelsets_0.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "log_time_ns,t_s [s],wheelset,y_left_n [N],q_left_n [N],y_right_n [N],q_right_n [N],\
         y_over_q_left [1],y_over_q_right [1],angle_of_attack_rad [rad],wear_number_left_n [N],\
         wear_number_right_n [N]"
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 101);
    assert!(rows[0].starts_with("100000000,0.1,"), "{}", rows[0]);
    assert!(rows[100].starts_with("200000000,0.2,"), "{}", rows[100]);
    let patches = std::fs::read_to_string(out_dir.join("contact_0_left.csv")).unwrap();
    assert_eq!(patches.lines().count(), 1 + 2 * 101);
    assert!(!out_dir.join("bodies_wheelset_0.csv").exists());

    // One topic to one named file.
    let file = dir.join("ws.csv");
    let (code, _, err) = railsim(&[
        "replay",
        log.to_str().unwrap(),
        "--topics",
        "/wheelsets/0",
        "--csv",
        file.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        std::fs::read_to_string(&file).unwrap().lines().count() as u64,
        1 + STEPS
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn plots_signals_to_a_png() {
    let dir = temp_dir("plot");
    let log = sample_log(&dir);
    let png = dir.join("yq.png");
    let (code, out, err) = railsim(&[
        "replay",
        log.to_str().unwrap(),
        "--plot",
        "/wheelsets/0:y_over_q_left,/wheelsets/0:y_over_q_right",
        "--png",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("plotted 2 signal(s), 800 samples"), "{out}");
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert!(bytes.len() > 10_000, "only {} bytes", bytes.len());

    // Several patches on one topic become separate lines.
    let png = dir.join("fn.png");
    let (code, out, err) = railsim(&[
        "replay",
        log.to_str().unwrap(),
        "--plot",
        "/contact/0/left:fn_n",
        "--from-s",
        "0.2",
        "--png",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("plotted 1 signal(s), 400 samples"), "{out}");
    assert!(png.exists());

    // One signal against another (a force against a displacement): the x range is the other
    // signal's, here the lateral position's ±1 mm.
    let png = dir.join("loop.png");
    let (code, out, err) = railsim(&[
        "replay",
        log.to_str().unwrap(),
        "--plot",
        "/wheelsets/0:y_left_n",
        "--against",
        "/bodies/wheelset_0:position.1",
        "--png",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("plotted 1 signal(s) against /bodies/wheelset_0:position.1 [m], 400 samples, -0.001 to 0.001"),
        "{out}"
    );
    assert!(std::fs::read(&png).unwrap().len() > 10_000);
    // against a topic with two messages per time: refused
    let (code, _, err) = railsim(&[
        "replay",
        log.to_str().unwrap(),
        "--plot",
        "/wheelsets/0:y_left_n",
        "--against",
        "/contact/0/left:fn_n",
        "--png",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("expected one"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_truncated_log_is_read_up_to_its_last_chunk_and_says_so() {
    let dir = temp_dir("truncated");
    let full = dir.join("full.mcap");
    write_log(
        &full,
        WriterOptions {
            chunk_size: 4096,
            flush_every: 100,
            zstd: true,
        },
    );
    let bytes = std::fs::read(&full).unwrap();
    let cut = dir.join("cut.mcap");
    std::fs::write(&cut, &bytes[..bytes.len() * 6 / 10]).unwrap();
    let (code, out, err) = railsim(&["replay", cut.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("was read without its summary") && err.contains("writer stopped"),
        "{err}"
    );
    assert!(
        out.contains("read without its summary, up to its last complete chunk"),
        "{out}"
    );
    let count: u64 = out
        .lines()
        .find(|l| l.trim_start().starts_with("/wheelsets/0"))
        .unwrap()
        .split_whitespace()
        .nth(2)
        .unwrap()
        .parse()
        .unwrap();
    assert!(count > 0 && count < STEPS, "{count} messages");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_input_exits_2_with_a_message() {
    let dir = temp_dir("bad");
    let log = sample_log(&dir);
    let log = log.to_str().unwrap();

    let missing = dir.join("missing.mcap");
    let (code, _, err) = railsim(&["replay", missing.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.starts_with(&format!("railsim: {}: opening the log:", missing.display())),
        "{err}"
    );

    let text = dir.join("notes.txt");
    std::fs::write(&text, "not a log at all\n").unwrap();
    let (code, _, err) = railsim(&["replay", text.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("not an MCAP file"), "{err}");

    let (code, _, err) = railsim(&["replay", log, "--topics", "/wheelsets/9", "--csv", "x"]);
    assert_eq!(code, 2);
    assert!(
        err.starts_with("railsim: ")
            && err.contains("unknown topic '/wheelsets/9'")
            && err.contains("/bodies/wheelset_0, /contact/0/left, /wheelsets/0"),
        "{err}"
    );

    let png = dir.join("never.png");
    let png = png.to_str().unwrap();
    let (code, _, err) = railsim(&["replay", log, "--plot", "/wheelsets/0:yq", "--png", png]);
    assert_eq!(code, 2);
    assert!(
        err.contains("unknown field 'yq' on topic '/wheelsets/0'") && err.contains("y_over_q_left"),
        "{err}"
    );
    let (code, _, err) = railsim(&["replay", log, "--plot", "/nope:x", "--png", png]);
    assert_eq!(code, 2);
    assert!(err.contains("unknown topic '/nope'"), "{err}");
    let (code, _, err) = railsim(&["replay", log, "--plot", "y_over_q_left", "--png", png]);
    assert_eq!(code, 2);
    assert!(err.contains("expected topic:field.path"), "{err}");
    let (code, _, err) = railsim(&["replay", log, "--from-s", "0.3", "--to-s", "0.1"]);
    assert_eq!(code, 2);
    assert!(err.contains("--from-s 0.3 is after --to-s 0.1"), "{err}");
    // a range beyond the log's messages (it exported an empty CSV and said nothing)
    let (code, _, err) = railsim(&["replay", log, "--from-s", "50", "--csv", "x"]);
    assert_eq!(code, 2);
    assert!(err.contains("the time range misses the log"), "{err}");
    let (code, _, err) = railsim(&["replay", log, "--from-s", "-1"]);
    assert_eq!(code, 2, "{err}");
    // beyond the nanosecond clock, printed short
    let (code, _, err) = railsim(&["replay", log, "--to-s", "1e300"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--to-s: expected a time from 0 to 1.84e10 s") && err.contains("found 1e300"),
        "{err}"
    );
    // a channel without messages: said so, not "no samples in the time range"
    let empty = dir.join("empty.mcap");
    let mut writer =
        LogWriter::create(&empty, &LogHeader::new(), WriterOptions::default()).unwrap();
    writer.channel::<WheelsetMessage>("/wheelsets/0").unwrap();
    writer.finish().unwrap();
    let empty = empty.to_str().unwrap();
    let plot = [
        "replay",
        empty,
        "--plot",
        "/wheelsets/0:y_over_q_left",
        "--png",
        png,
    ];
    let (code, _, err) = railsim(&plot);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("the log has no messages on topic '/wheelsets/0'"),
        "{err}"
    );
    assert!(!Path::new(png).exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// A log cut to any length up to 100 bytes (inside the magic, the MCAP header or the
/// `railsim_log` metadata record) and a finished log whose footer puts the summary beyond the
/// footer: exit 2 with a message naming the file and its size, never a bare OS error (a log cut
/// to 8 or 10 bytes said `seeking the summary: Invalid argument (os error 22)`).
#[test]
fn a_cut_or_damaged_log_exits_2_naming_the_file_and_its_size() {
    let dir = temp_dir("short");
    let bytes = std::fs::read(sample_log(&dir)).unwrap();
    let cut = dir.join("cut.mcap");
    for len in 0..=100 {
        std::fs::write(&cut, &bytes[..len]).unwrap();
        let (code, out, err) = railsim(&["replay", cut.to_str().unwrap()]);
        assert_eq!(code, 2, "cut at {len}: {out}{err}");
        assert!(
            err.starts_with(&format!(
                "railsim: {}: not a complete railsim log",
                cut.display()
            )) && err.contains(&format!("the file is {len} bytes long"))
                && err.contains("expected at least the MCAP magic")
                && !err.contains("os error"),
            "cut at {len}: {err}"
        );
    }

    // The footer's summary start (its first 8 body bytes) damaged.
    let footer = bytes.len() - 37;
    assert_eq!(bytes[footer], 0x02, "no footer record at {footer}");
    let damaged = dir.join("damaged.mcap");
    for summary_start in [u64::MAX, 1 << 63, bytes.len() as u64 + 100, footer as u64] {
        let mut b = bytes.clone();
        b[footer + 9..footer + 17].copy_from_slice(&summary_start.to_le_bytes());
        std::fs::write(&damaged, &b).unwrap();
        let (code, out, err) = railsim(&["replay", damaged.to_str().unwrap()]);
        assert_eq!(code, 2, "summary at {summary_start}: {out}{err}");
        assert!(
            err.starts_with(&format!(
                "railsim: {}: not a complete MCAP file",
                damaged.display()
            )) && err.contains("its footer is damaged")
                && err.contains(&format!("the file is {} bytes long", bytes.len()))
                && err.contains(&format!("puts the summary at byte {summary_start}"))
                && !err.contains("os error"),
            "summary at {summary_start}: {err}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `--png` takes a `.png` name (any case), checked before the log is read; a file that cannot
/// be created is said plainly. Before, `--png out/a.txt` drew the whole plot and then failed
/// with `ImageError(Unsupported(UnsupportedError { .. }))`.
#[test]
fn the_plot_file_must_be_a_png_that_can_be_created() {
    let dir = temp_dir("png");
    let log = sample_log(&dir);
    let log = log.to_str().unwrap();
    let plot = |png: &Path| {
        railsim(&[
            "replay",
            log,
            "--plot",
            "/wheelsets/0:y_over_q_left",
            "--png",
            png.to_str().unwrap(),
        ])
    };
    let txt = dir.join("a.txt");
    let (code, _, err) = plot(&txt);
    assert_eq!(code, 2, "{err}");
    assert_eq!(
        err.trim_end(),
        format!(
            "railsim: --png {}: expected a file name ending in .png, found extension \"txt\"",
            txt.display()
        )
    );
    assert!(!txt.exists());
    // checked before the log is opened
    let (code, _, err) = railsim(&[
        "replay",
        dir.join("missing.mcap").to_str().unwrap(),
        "--plot",
        "/wheelsets/0:y_over_q_left",
        "--png",
        txt.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--png") && !err.contains("missing.mcap"),
        "{err}"
    );
    let (code, _, err) = plot(&dir.join("plot"));
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("found no extension"), "{err}");

    let upper = dir.join("A.PNG");
    let (code, _, err) = plot(&upper);
    assert_eq!(code, 0, "{err}");
    assert_eq!(&std::fs::read(&upper).unwrap()[..8], b"\x89PNG\r\n\x1a\n");

    let nowhere = dir.join("no_such_dir").join("a.png");
    let (code, _, err) = plot(&nowhere);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.starts_with(&format!(
            "railsim: {}: creating the PNG: ",
            nowhere.display()
        )) && !err.contains("Error("),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The value of the `integrator` line of the scene listing of `log`.
fn listed_integrator(log: &Path) -> String {
    let (code, out, err) = railsim(&["replay", log.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    out.lines()
        .find_map(|l| {
            let (key, value) = l.split_once(" = ")?;
            (key.trim() == "integrator").then(|| value.to_owned())
        })
        .unwrap_or_else(|| panic!("no integrator line:\n{out}"))
}

/// The scene listing gives the integrator in the scene file's terms (`[integrator]` in
/// docs/formats/scene.md), not as the debug dump of `railsim_ode::Method` that `railsim run`
/// stores (`DormandPrince { rtol: 0.0001, atol: 1e-6, h0: None, h_max: inf }`).
#[test]
fn the_scene_listing_gives_the_integrator_in_scene_file_terms() {
    let dir = temp_dir("integrator");
    let log = dir.join("i.mcap");
    // as `railsim run` stores it
    let (code, _, err) = railsim(&[
        "run",
        "scenes/free_wheelset_klingel.toml",
        "--duration-s",
        "0.05",
        "--out",
        log.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        listed_integrator(&log),
        "dopri5, rtol 1e-7, atol 1e-9, max_step_s unlimited"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Output into a pipe whose reader has gone (`railsim replay LOG | head`): a quiet, successful
/// end, not a panic (`println!` panics on the broken pipe).
#[test]
fn a_closed_output_pipe_ends_quietly() {
    let dir = temp_dir("pipe");
    let log = sample_log(&dir);
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_railsim"))
        .args(["replay", log.to_str().unwrap()])
        .stdout(writer)
        .stderr(std::process::Stdio::piped())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(err.is_empty(), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

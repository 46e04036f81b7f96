//! `railsim run`: a scene end to end through the binary, its log read back, re-run from the log,
//! a run killed with SIGKILL, and bad scenes.

use crate::common;
use common::railsim;
use common::root;

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn temp_dir(name: &str) -> PathBuf {
    common::temp_dir("run", name)
}

/// The `simulation stopped ...` line of a run's standard error.
fn err_line(err: &str) -> String {
    err.lines()
        .find(|l| l.contains("simulation stopped at"))
        .unwrap_or("")
        .to_owned()
}

#[test]
fn runs_a_scene_writes_a_readable_log_and_reruns_it_identically() {
    let dir = temp_dir("klingel");
    let log = dir.join("k.mcap");
    let log_s = log.to_str().unwrap();
    let (code, out, err) = railsim(&[
        "run",
        "scenes/free_wheelset_klingel.toml",
        "--duration-s",
        "0.5",
        "--out",
        log_s,
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    // 18 km/h with DOPRI5: the note before the run names the faster integrator
    assert!(
        err.contains("note: at 18 km/h the creep forces' damping")
            && err.contains("radau5 at rtol 1e-5, atol 1e-7")
            && err.contains("can damp out an oscillation it does not resolve"),
        "{err}"
    );
    for key in [
        "real-time factor",
        "max |lateral displacement|",
        "max Y/Q",
        "EN 14363 assessment, maxima at a sample and energies from the run's samples at 1000 Hz",
        "track-shift force ΣY (EN 14363",
        "wheelset 0 (ws): (ΣY)2m max",
        "integrator:",
        "state digest",
    ] {
        assert!(out.contains(key), "summary lacks '{key}':\n{out}");
    }
    let reader = railsim_log::LogReader::open(&log).unwrap();
    assert!(reader.is_complete());
    // 0.5 s at 200 Hz: 101 samples on each of the scene's three topic kinds.
    assert_eq!(reader.channel("/bodies/ws").unwrap().message_count, 101);
    assert_eq!(reader.channel("/wheelsets/0").unwrap().message_count, 101);
    // the scene logs no contact topic: no empty contact channels either
    assert!(
        reader.channel("/contact/0/left").is_none(),
        "{:?}",
        reader
            .channels()
            .iter()
            .map(|c| &c.topic)
            .collect::<Vec<_>>()
    );
    assert!(reader.metadata().contains_key("railsim_sources"));
    // the scene's rates: a 200 Hz log, assessed by default at 1 kHz
    let scene = reader.scene().unwrap();
    assert_eq!(scene.get("log_rate_hz").map(String::as_str), Some("200"));
    assert_eq!(
        scene.get("assessment_rate_hz").map(String::as_str),
        Some("1000")
    );
    // The wheelset's logged angular velocity includes its spin: V / r0 about the axle at
    // forward rolling (10 m/s on r0 = 0.46 m, conical wheels; it was logged as 0).
    let ws = reader
        .read_topic::<railsim_log::messages::BodyState>("/bodies/ws", None)
        .unwrap();
    for (_, m) in &ws {
        let rolling = m.velocity[0] / 0.46;
        assert!(
            (m.angular_velocity[1] / rolling - 1.0).abs() < 0.01,
            "t {}: spin {} rad/s, V / r0 {rolling}",
            m.t_s,
            m.angular_velocity[1]
        );
    }
    // the listing says where the run ended (--duration-s 0.5, not the scene's duration_s)
    let (code, out, err) = railsim(&["replay", log_s]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("\nrun: ended at t = 0.5 s, state digest "),
        "{out}"
    );
    // ... and, with the scene, where it was to end (a killed run has no result to say it)
    let run_to = out.lines().find(|l| l.contains("run_to_s"));
    assert!(
        run_to.is_some_and(|l| l.trim_end().ends_with("0.5")),
        "{out}"
    );
    let (code, out, err) = railsim(&["replay", log_s, "--rerun"]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("agrees"), "{out}");
    // ... from another directory too: the log names its files by absolute paths (they were
    // relative to the directory the run started in)
    let elsewhere = Command::new(env!("CARGO_BIN_EXE_railsim"))
        .args(["replay", log_s, "--rerun"])
        .current_dir(&dir)
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&elsewhere.stdout);
    assert_eq!(
        elsewhere.status.code(),
        Some(0),
        "{out}{}",
        String::from_utf8_lossy(&elsewhere.stderr)
    );
    assert!(out.contains("agrees"), "{out}");
    // --rerun does not list, export or plot: combined with those options it is refused
    let csv = dir.join("x.csv");
    let (code, _, err) = railsim(&["replay", log_s, "--rerun", "--csv", csv.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--rerun") && err.contains("--csv"), "{err}");
    assert!(!csv.exists());
    // an export into the log itself, or into a file that is not a CSV, is refused
    for bad in [log_s, dir.join("x.mcap").to_str().unwrap()] {
        let (code, _, err) = railsim(&["replay", log_s, "--csv", bad, "--topics", "/bodies/ws"]);
        assert_eq!(code, 2, "{bad}: {err}");
        assert!(err.contains("--csv"), "{err}");
    }
    assert!(railsim_log::LogReader::open(&log).unwrap().is_complete());
    std::fs::remove_dir_all(&dir).ok();
}

/// The README's first example runs to its end: the Klingel scene (a free conical wheelset,
/// whose kinematic mode is slightly unstable) reached the 40 mm derailment limit at 9.7 s when it
/// ran at 10 m/s from 3 mm; now 5 m/s from 1 mm, 100 m.
/// A log records the digests of the data files its scene read (rail profile, measured
/// irregularities), so that `replay --rerun` names the one that changed or went missing instead
/// of reporting only that the states differ.
#[test]
fn a_rerun_names_the_data_file_that_changed_since_the_log() {
    let dir = temp_dir("data-files");
    std::fs::create_dir_all(dir.join("irregularities")).unwrap();
    let csv = dir.join("irregularities/example_measured.csv");
    std::fs::copy(
        root().join("tracks/irregularities/example_measured.csv"),
        &csv,
    )
    .unwrap();
    let rail = dir.join("rail.prr");
    std::fs::copy(root().join("tracks/profiles/MBench_UIC60_v3.prr"), &rail).unwrap();
    let track = std::fs::read_to_string(root().join("tracks/straight_measured_example.toml"))
        .unwrap()
        .replace(
            r#"rail_profile = { left = "uic60", right = "uic60" }"#,
            r#"rail_profile = { left = "rail.prr", right = "rail.prr" }"#,
        );
    assert!(track.contains("rail.prr"));
    std::fs::write(dir.join("track.toml"), track).unwrap();
    let scene = dir.join("scene.toml");
    let vehicle = root().join("scenes/vehicles/wheelset_free_cone.toml");
    std::fs::write(
        &scene,
        format!(
            "name = \"data files\"\nvehicle = {vehicle:?}\ntrack = \"track.toml\"\nspeed_kmh = 18\n\
             distance_m = 1\n[contact]\nmodel = \"polach\"\n[log]\nrate_hz = 200\n"
        ),
    )
    .unwrap();
    let log = dir.join("d.mcap");
    let (log_s, scene_s) = (log.to_str().unwrap(), scene.to_str().unwrap());
    let (code, _, err) = railsim(&["run", scene_s, "--out", log_s, "--quiet"]);
    assert_eq!(code, 0, "{err}");
    // one line per file, the rail profile of both rails once
    let reader = railsim_log::LogReader::open(&log).unwrap();
    let listed = reader.metadata()["railsim_sources"]["data_files"].clone();
    let abs = |p: &std::path::Path| std::fs::canonicalize(p).unwrap().display().to_string();
    assert_eq!(listed.lines().count(), 2, "{listed}");
    for (line, file) in listed.lines().zip([&rail, &csv]) {
        assert!(
            line.starts_with("fnv1a64:") && line.ends_with(&format!(" {}", abs(file))),
            "{line}"
        );
    }
    let (code, out, err) = railsim(&["replay", log_s, "--rerun"]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("agrees"), "{out}");
    // one irregularity value changed by 1 µm: named, and no re-run
    let text = std::fs::read_to_string(&csv).unwrap();
    std::fs::write(&csv, text.replacen("0.5,0.030,", "0.5,0.031,", 1)).unwrap();
    let (code, out, err) = railsim(&["replay", log_s, "--rerun"]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains(&format!(
            "the data file {} changed since the log was written",
            abs(&csv)
        )) && !out.contains("re-ran"),
        "{out}{err}"
    );
    // a data file gone: named
    std::fs::write(&csv, text).unwrap();
    std::fs::remove_file(&rail).unwrap();
    let (code, _, err) = railsim(&["replay", log_s, "--rerun"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("rail.prr") && err.contains("named in the log"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_readmes_klingel_scene_runs_to_its_end() {
    let (code, out, err) = railsim(&[
        "run",
        "scenes/free_wheelset_klingel.toml",
        "--no-log",
        "--quiet",
    ]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("simulated 20.000 s"), "{out}");
    let max: f64 = out
        .lines()
        .find_map(|l| l.strip_prefix("wheelset 0 (ws): max |lateral displacement| "))
        .and_then(|v| v.trim_end_matches(" mm").parse().ok())
        .unwrap_or_else(|| panic!("{out}"));
    assert!(max > 1.0 && max < 4.0, "{max} mm");
}

#[test]
fn a_run_killed_with_sigkill_leaves_a_readable_log() {
    let dir = temp_dir("kill");
    let log = dir.join("killed.mcap");
    let mut child = Command::new(env!("CARGO_BIN_EXE_railsim"))
        .args(["run", "--quiet", "--out", log.to_str().unwrap()])
        .current_dir(root())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // Wait until complete chunks (or a flush, every 4096 messages) have reached the file, then
    // kill.
    let start = Instant::now();
    while std::fs::metadata(&log).map_or(0, |m| m.len()) < 200_000 {
        assert!(start.elapsed() < Duration::from_secs(300), "no log growth");
        std::thread::sleep(Duration::from_millis(100));
    }
    child.kill().unwrap(); // SIGKILL on Unix
    child.wait().unwrap();
    let reader = railsim_log::LogReader::open(&log).unwrap();
    assert!(!reader.is_complete());
    assert!(reader.message_count() > 100, "{}", reader.message_count());
    let (t0, t1) = reader.time_range().unwrap();
    assert!(t1 > t0);
    std::fs::remove_dir_all(&dir).ok();
}

/// A run whose log cannot be written (here a file-size limit of 300 kB) stops with the cause,
/// and the log keeps what was written: before stop 39 the writer's refusal to close the
/// failed log ("attempted another write after a write method failed") replaced the cause.
#[cfg(unix)]
#[test]
fn a_failed_log_write_reports_its_cause() {
    let dir = temp_dir("file_limit");
    let log = dir.join("limited.mcap");
    let script = format!(
        "trap '' XFSZ; ulimit -f 600; exec '{}' run --quiet --duration-s 3 --out '{}'",
        env!("CARGO_BIN_EXE_railsim"),
        log.display()
    );
    let out = Command::new("sh")
        .args(["-c", &script])
        .current_dir(root())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("File too large"), "{err}");
    assert!(!err.contains("attempted another write"), "{err}");
    let reader = railsim_log::LogReader::open(&log).unwrap();
    assert!(reader.message_count() > 100, "{}", reader.message_count());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_scenes_exit_2_with_located_messages() {
    let dir = temp_dir("bad");
    let scene = dir.join("bad.toml");
    std::fs::write(
        &scene,
        format!(
            "vehicle = \"{}\"\ntrack = \"{}\"\nspeed_kmh = -5\nduration_s = 1\nbogus = 1\n",
            root().join("vehicles/wheelset_free.toml").display(),
            root().join("tracks/straight.toml").display()
        ),
    )
    .unwrap();
    let (code, _, err) = railsim(&["run", scene.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("bad.toml:3:"), "{err}");
    assert!(err.contains("speed_kmh"), "{err}");
    assert!(
        err.contains("bad.toml:5:") && err.contains("bogus"),
        "{err}"
    );
    let (code, _, err) = railsim(&["run", "no/such/scene.toml"]);
    assert_eq!(code, 2);
    assert!(err.contains("no/such/scene.toml"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A stop with integrator settings that can produce it numerically carries a note saying so
/// and how to tell: the default scene with fixed-step RK4 at 5 ms (beyond the explicit stability
/// limit) "derails" at t = 0.03 s; at the shipped 2 ms no note would be printed.
#[test]
fn a_stop_with_a_long_fixed_step_notes_the_stability_limit() {
    let dir = temp_dir("rk4-note");
    let text = std::fs::read_to_string(root().join("scenes/default.toml")).unwrap();
    let scenes = root().join("scenes");
    let start = text.find("[integrator]").unwrap();
    let end = start + text[start..].find("[log]").unwrap();
    let text = format!(
        "{}[integrator]\nmethod = \"rk4\"\nstep_s = 0.005\n\n{}",
        &text[..start],
        &text[end..]
    )
    .replace("\"../", &format!("\"{}/../", scenes.display()));
    let scene = dir.join("rk4.toml");
    std::fs::write(&scene, text).unwrap();
    let log = dir.join("rk4.mcap");
    let log_s = log.to_str().unwrap();
    let (code, out, err) = railsim(&[
        "run",
        scene.to_str().unwrap(),
        "--duration-s",
        "0.06",
        "--out",
        log_s,
        "--quiet",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("simulation stopped at t = "), "{err}");
    // The summary and the assessment of the samples before the stop are printed first, headed
    // by the stop's time.
    let t_stop = |text: &str, key: &str| {
        let at = text.find(key).map(|i| i + key.len())?;
        text[at..].split_whitespace().next().map(str::to_owned)
    };
    assert_eq!(
        t_stop(&out, "run STOPPED at t = "),
        t_stop(&err, "simulation stopped at t = "),
        "{out}\n{err}"
    );
    assert!(
        out.contains("track-shift force ΣY") && out.contains("; state digest "),
        "{out}"
    );
    assert!(
        err.contains("note: the run used a fixed explicit step of 5 ms; above about 2.00 ms")
            && err.contains("rerun with a smaller step_s"),
        "{err}"
    );
    // The kept log says that the run stopped, when and why (its scene's duration_s says where
    // it was to end) ...
    let (code, out, err) = railsim(&["replay", log_s]);
    assert_eq!(code, 0, "{err}");
    let line = out.lines().find(|l| l.starts_with("run: ")).unwrap_or("");
    assert!(
        line.starts_with("run: STOPPED at t = 0.0") && err.is_empty(),
        "{out}{err}"
    );
    let stop = err_line(
        &railsim(&[
            "run",
            scene.to_str().unwrap(),
            "--duration-s",
            "0.06",
            "--no-log",
            "--quiet",
        ])
        .2,
    );
    assert!(
        stop.contains(&line["run: STOPPED at ".len()..]),
        "{line}\n{stop}"
    );
    // ... and a re-run stops in the same state.
    let (code, out, err) = railsim(&["replay", log_s, "--rerun"]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains("stopped at t = 0.0") && out.contains("agrees"),
        "{out}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// On an elastic rail support the rail masses on the contact stiffness lower the explicit
/// stability limit: the default scene's RK4 step of 2 ms, stable on rigid rails, stops at
/// once, and the note names the rail masses and the lower limit (0.89 ms for 150 kg).
#[test]
fn a_stop_on_an_elastic_rail_support_notes_its_lower_stability_limit() {
    let dir = temp_dir("rk4-rails");
    let track = std::fs::read_to_string(root().join("tracks/straight_elastic.toml")).unwrap();
    std::fs::write(dir.join("track.toml"), track).unwrap();
    let scene = dir.join("rk4.toml");
    std::fs::write(
        &scene,
        format!(
            "vehicle = \"{}\"\ntrack = \"track.toml\"\nspeed_kmh = 198\nduration_s = 0.1\n\
             [integrator]\nmethod = \"rk4\"\nstep_s = 0.002\n",
            root().join("vehicles/manchester_vehicle1.toml").display()
        ),
    )
    .unwrap();
    let (code, _, err) = railsim(&["run", scene.to_str().unwrap(), "--no-log", "--quiet"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("simulation stopped at t = "), "{err}");
    assert!(
        err.contains("fixed explicit step of 2 ms; above about 0.89 ms")
            && err.contains("150 kg rail masses"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `--threads` changes where the wheels' contact evaluations run, not the results: the
/// Manchester vehicle on irregular track gives the same state digest on one thread and on two,
/// and the summary reports the per-wheel EN 14363 quantities and the bogie frames.
#[test]
fn threads_do_not_change_the_run() {
    let digest = |threads: &str| {
        let (code, out, err) = railsim(&[
            "--threads",
            threads,
            "run",
            "scenes/manchester_straight_irregular.toml",
            "--duration-s",
            "0.3",
            "--no-log",
            "--quiet",
        ]);
        assert_eq!(code, 0, "{err}");
        // 198 km/h: no low-speed note
        assert!(!err.contains("note: at "), "{err}");
        for key in [
            "running safety and vertical force per wheel (EN 14363",
            "wheelset 0 (ws1) left: (Y/Q)2m",
            "; Q min ",
            "bogie frames, simplified stability method",
            // (no peak: a record under 2 s has no instability frequency to band-pass around)
            "bogie_front above ws1: no peak (no band)",
            "no instability frequency (a record under 2 s has none)",
        ] {
            assert!(out.contains(key), "summary lacks '{key}':\n{out}");
        }
        out.lines()
            .find_map(|l| l.split("state digest ").nth(1).map(str::to_owned))
            .expect("a digest")
    };
    assert_eq!(digest("1"), digest("2"));
}

/// A vehicle on ideal straight track gives DOPRI5 nothing to resolve: its steps are held by
/// stability, and the summary says so and names the remedy.
#[test]
fn a_stability_limited_run_is_reported() {
    let dir = temp_dir("stiff");
    let scene = dir.join("stiff.toml");
    std::fs::write(
        &scene,
        format!(
            "vehicle = \"{}\"\ntrack = \"{}\"\nspeed_kmh = 72\nduration_s = 0.3\n\
             freeze = [\"carbody.x\"]\n[contact]\nmodel = \"polach\"\n\
             [integrator]\nmethod = \"dopri5\"\nrtol = 1e-4\natol = 1e-6\n",
            root().join("vehicles/manchester_vehicle1.toml").display(),
            root().join("tracks/straight.toml").display()
        ),
    )
    .unwrap();
    let (code, out, err) = railsim(&["run", scene.to_str().unwrap(), "--no-log"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("limited by stability), ")
            && out.contains("integrator: the steps were limited by stability, not accuracy (")
            && out.contains("stiff from t = 0.0")
            && out.contains("a smaller atol shrinks it in proportion"),
        "{out}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A scene that starts inside a curve from its quasi-static state: the run says how the state
/// was found, and the vehicle is at its steady lateral position from the first sample.
#[test]
fn a_quasi_static_start_is_reported() {
    let dir = temp_dir("quasi_static");
    let scene = dir.join("in_curve.toml");
    std::fs::write(
        &scene,
        format!(
            "vehicle = \"{}\"\ntrack = \"{}\"\nspeed_kmh = 80\nstart_m = 420\nduration_s = 0.2\n\
             freeze = [\"carbody.x\"]\n[contact]\nmodel = \"polach\"\n[initial]\nstate = \"quasi-static\"\n",
            root().join("vehicles/manchester_vehicle1.toml").display(),
            root().join("tracks/curve_r300.toml").display()
        ),
    )
    .unwrap();
    let (code, out, err) = railsim(&["run", scene.to_str().unwrap(), "--no-log"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("initial state: quasi-static at s = 420.00 m (")
            && err.contains("Newton iterations, largest residual"),
        "{err}"
    );
    // the leading wheelset runs 6.28 mm out toward the outer rail throughout
    assert!(
        out.contains("wheelset 0 (ws1): max |lateral displacement| 6.28 mm"),
        "{out}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The low-speed note: the rigid-rail R = 150 m scene at 40 km/h runs DOPRI5 and gets it; the
/// elastic-rail scene runs Radau5 since stop 31 (4.4 s against DOPRI5's 55.6 s, once STRIPES
/// integrated the junctions of the profiles' arcs at sub-points) and gets none. Until then the
/// note excepted STRIPES on an elastic rail support, where Radau5 had been the slower.
#[test]
fn the_low_speed_note_comes_with_an_explicit_method_only() {
    // the scene's first 10 ms, no log: the note comes before the run (standard error)
    let note_of = |scene: &str| {
        let (code, _, err) =
            railsim(&["run", scene, "--duration-s", "0.01", "--no-log", "--quiet"]);
        assert_eq!(code, 0, "{err}");
        err
    };
    let elastic = note_of("scenes/manchester_r150_40kmh_elastic.toml");
    assert!(!elastic.contains("note: at 40 km/h"), "{elastic}");
    let rigid = note_of("scenes/manchester_r150_40kmh.toml");
    assert!(
        rigid.contains("note: at 40 km/h the creep forces' damping")
            && !rigid.contains("elastic rail support"),
        "{rigid}"
    );
}

/// The aliasing note (docs/models/dynamics.md, "Aliasing"): a run whose assessment samples come
/// at less than 1 kHz (only a scene's own `[assessment] rate_hz` can set that) is told that its
/// EN 14363 statistics come from unfiltered samples; the default scene (a 200 Hz log, assessed
/// by default at 1 kHz), or the same with `[assessment] rate_hz = 1000`, is not. A rate that is
/// no whole multiple of the log rate is refused, naming the key.
#[test]
fn an_assessment_rate_below_one_kilohertz_notes_its_aliasing() {
    let dir = temp_dir("aliasing-note");
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(root().join("scenes/default.toml"))
        .unwrap()
        .replace("\"../", &format!("\"{}/", root().display()));
    assert!(text.contains("rate_hz = 200") && !text.contains("[assessment]"));
    // the default scene with `[assessment] rate_hz` and contact model `model`
    let with_rate = |name: &str, rate_hz: u32, model: &str| {
        let path = dir.join(name);
        let scene = format!("{text}\n[assessment]\nrate_hz = {rate_hz}\n")
            .replace("model = \"stripes\"", &format!("model = \"{model}\""));
        std::fs::write(&path, scene).unwrap();
        path.to_str().unwrap().to_owned()
    };
    let aliased = with_rate("aliased.toml", 200, "stripes");
    let assessed = with_rate("assessed.toml", 1000, "stripes");
    let uneven = with_rate("uneven.toml", 1100, "stripes");
    // a Hertz model's default is 2 kHz: 1 kHz is below it
    let hertz_1k = with_rate("hertz_1k.toml", 1000, "polach");
    let run = |scene: &str| railsim(&["run", scene, "--duration-s", "0.01", "--no-log", "--quiet"]);
    let (code, _, err) = run(&aliased);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("note: the EN 14363 statistics below come from samples at 200 Hz")
            && err.contains("above 100 Hz"),
        "{err}"
    );
    for scene in ["scenes/default.toml", &assessed] {
        let (code, _, err) = run(scene);
        assert_eq!(code, 0, "{err}");
        assert!(!err.contains("anti-aliasing"), "{err}");
    }
    let (code, _, err) = run(&hertz_1k);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("samples at 1000 Hz ([assessment] rate_hz)")
            && err.contains("at or above 2000 Hz for contact model polach"),
        "{err}"
    );
    let (code, _, err) = run(&uneven);
    assert_ne!(code, 0);
    assert!(
        err.contains("rate_hz = 1100 Hz: expected a whole multiple of the log rate"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `[assessment] vertical_weighting = "iso2631-4"` is named beside N_MV in the summary (and the
/// default weighting is not): the bogie of `bogie_two_axle.toml` (its frame the carbody) for 6 s
/// at 10 m/s on ideal straight track, `polach`.
#[test]
fn the_summary_names_iso_2631_4_s_w_b() {
    let dir = temp_dir("vertical-weighting");
    std::fs::create_dir_all(&dir).unwrap();
    let iso = short_bogie_run(
        &dir,
        "iso.toml",
        "[assessment]\nvertical_weighting = \"iso2631-4\"\n",
    );
    let default = short_bogie_run(&dir, "default.toml", "");
    for (path, named) in [(iso, true), (default, false)] {
        let (code, out, err) = railsim(&["run", &path, "--no-log", "--quiet"]);
        assert_eq!(code, 0, "{err}");
        let line = out
            .lines()
            .find(|l| l.contains("EN 12299 N_MV"))
            .unwrap_or_else(|| panic!("no N_MV in\n{out}"));
        assert_eq!(line.contains("(W_b of ISO 2631-4)"), named, "{line}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A scene file `name` in `dir`: the two-axle bogie at 36 km/h for 6 s (60 m) on straight
/// track, `polach`, the leading wheelset 1 mm off centre, with `extra` appended; its path.
fn short_bogie_run(dir: &std::path::Path, name: &str, extra: &str) -> String {
    let path = dir.join(name);
    let text = format!(
        "vehicle = \"{root}/vehicles/bogie_two_axle.toml\"\ntrack = \"{root}/tracks/straight.toml\"\n\
         speed_kmh = 36\nduration_s = 6\n[contact]\nmodel = \"polach\"\n[initial]\n\
         lateral_offset_mm = 1.0\n{extra}",
        root = root().display()
    );
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_owned()
}

#[test]
fn the_summary_lists_the_per_section_statistics() {
    let dir = temp_dir("sections");
    std::fs::create_dir_all(&dir).unwrap();
    let sections = short_bogie_run(
        &dir,
        "sections.toml",
        // (a Q limit between the rear wheelset's largest section and its estimate)
        "[assessment]\nsection_length_m = 10\nsection_k = 3\nq_limit_kn = 16.3\n",
    );
    let csv = dir.join("sections.csv");
    let csv_arg = csv.to_str().unwrap();
    let (code, out, err) = railsim(&[
        "run",
        &sections,
        "--no-log",
        "--quiet",
        "--sections-csv",
        csv_arg,
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("per track section of 10 m"), "{out}");
    assert!(out.contains("estimate mean + k s with k = 3"), "{out}");
    // the wheelsets run over some 60 m of straight track: five or six whole 10 m sections
    // each, all off curves, for every axle and wheel and the frame's measuring point
    let counts: Vec<usize> = out
        .lines()
        .flat_map(|l| l.split("; "))
        .filter_map(|part| {
            let rest = part.split(" off curves ").nth(1)?;
            rest.split(' ').next()?.parse().ok()
        })
        .collect();
    // two axles, for each of four wheels (Y/Q)2m and Q, and at the one measuring point (the
    // frame's centre) the lateral and vertical acceleration's maximum and r.m.s.
    assert_eq!(counts.len(), 2 + 4 * 2 + 4, "{out}");
    // each part: its estimate is mean + 3 s, and it is EXCEEDED where the estimate is above the
    // limit (the estimate, not the largest section, is judged)
    let number = |part: &str, key: &str| -> Option<f64> {
        let rest = &part[part.find(key)? + key.len()..];
        rest.split([' ', ',']).next()?.parse().ok()
    };
    let mut verdicts = [0; 2];
    let block = out
        .lines()
        .skip_while(|l| !l.starts_with("per track section"))
        .skip(1);
    for part in block.take(2 + 4 + 1).flat_map(|l| l.split("; ")) {
        let (Some(mean), Some(s), Some(estimate)) = (
            number(part, "mean "),
            number(part, ", s "),
            number(part, "estimate "),
        ) else {
            continue;
        };
        assert!((estimate - (mean + 3.0 * s)).abs() < 2.5e-3, "{part}");
        if let Some(limit) = number(part, "limit ") {
            let exceeded = part.ends_with(" EXCEEDED");
            assert_eq!(exceeded, estimate > limit, "{part}");
            verdicts[usize::from(exceeded)] += 1;
        }
    }
    assert!(verdicts[0] > 0 && verdicts[1] > 0, "{verdicts:?}\n{out}");
    assert!(counts.iter().all(|&n| (5..=6).contains(&n)), "{counts:?}");
    // the CSV: a row per section of each, 10 m long, in SI units; its largest (ΣY)2m of the
    // leading axle is the summary's (in kN, three decimals)
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("quantity,unit,wheelset,name,side,zone,section_start_m,section_end_m,value")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), counts.iter().sum::<usize>(), "{text}");
    for r in &rows {
        let (a, b): (f64, f64) = (r[6].parse().unwrap(), r[7].parse().unwrap());
        assert!((b - a - 10.0).abs() < 1e-9 && r[5] == "off_curves", "{r:?}");
    }
    let largest = rows
        .iter()
        .filter(|r| r[0] == "sum_y_2m" && r[2] == "0")
        .map(|r| r[8].parse::<f64>().unwrap())
        .fold(f64::NEG_INFINITY, f64::max);
    let line = out
        .lines()
        .skip_while(|l| !l.starts_with("per track section"))
        .nth(1)
        .unwrap();
    assert!(
        line.contains(&format!("largest {:.3} kN", largest * 1e-3)),
        "{largest} N against\n{line}"
    );
    let plain = short_bogie_run(&dir, "plain.toml", "");
    let (code, out, err) = railsim(&["run", &plain, "--no-log", "--quiet"]);
    assert_eq!(code, 0, "{err}");
    assert!(!out.contains("per track section"), "{out}");
    // a CSV of sections needs the scene's sections, checked before the run
    let (code, out, err) = railsim(&["run", &plain, "--no-log", "--sections-csv", csv_arg]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("sets no [assessment] section_length_m"),
        "{err}"
    );
    assert!(out.is_empty(), "{out}");
    std::fs::remove_dir_all(&dir).ok();
}

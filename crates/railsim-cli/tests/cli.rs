//! The `railsim` command line: the README's main job, batch mode and exit codes.

use crate::common;
use common::railsim;

#[test]
fn default_contact_job_runs() {
    let (code, out, err) = railsim(&["contact"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("1 patch(es)") && out.contains("Fz = 10000.0 N"),
        "{out}"
    );
}

#[test]
fn batch_mode_writes_contact_columns() {
    let dir = common::temp_dir("cli", "batch");
    let cases = dir.join("cases.csv");
    std::fs::write(
        &cases,
        "case,side,y_ws_mm,yaw_ws_rad,roll_ws_rad,vpitch_rad_s,fz_target_N\n\
         a,left,0,0,0,-4.3481181,10000\nb,right,6.5,0.0156,-0.004376,-4.3293718,10000\n",
    )
    .unwrap();
    let out = dir.join("out.csv");
    let (code, _, err) = railsim(&[
        "contact",
        "--cases",
        cases.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    assert!(
        lines
            .next()
            .unwrap()
            .starts_with("case,side,icp,z_ws_mm,ycp_r_mm,delttr_rad,pen_mm,fn_N,fx_N,fs_N")
    );
    assert_eq!(lines.count(), 2);
    std::fs::remove_dir_all(&dir).ok();
}

/// Where the vertical force jumps across a prescribed load (no height carries it), the closest
/// height is printed with a warning, not passed off as the load: `polach` on the right wheel
/// pushed 6.7 mm into its flange (the Hertz patch's curvatures change abruptly in the conformal
/// flange root: 150 kN at one height, 46 kN 10 µm higher), also by case in a batch, where
/// `stripes` carries the same loads.
#[test]
fn a_load_that_no_height_carries_is_reported() {
    let (code, out, err) = railsim(&[
        "contact",
        "--model",
        "polach",
        "--side",
        "right",
        "--y-mm",
        "-6.735",
        "--yaw-mrad",
        "2",
        "--load-kn",
        "55",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("warning: no height carries the load of 55000.0 N"),
        "{out}"
    );
    assert!(!out.contains("Fz = 55000.0 N"), "{out}");
    let (_, out, _) = railsim(&["contact", "--load-kn", "55"]);
    assert!(
        out.contains("Fz = 55000.0 N") && !out.contains("warning"),
        "{out}"
    );
    // In a batch: a flange pose that `polach` misses is reported by case; `stripes` at its 1 mm
    // default carries both loads (before its junction segments, the flange zone of case b
    // appeared between two heights and the 1 mm step could not carry 55 kN there either).
    let dir = common::temp_dir("cli", "load_missed");
    let cases = dir.join("cases.csv");
    std::fs::write(
        &cases,
        "case,side,y_ws_mm,yaw_ws_rad,roll_ws_rad,vpitch_rad_s,fz_target_N\n\
         a,right,6.5,0.002,0,-4.3481181,55000\nb,right,6.685,0.002,0,-4.3481181,55000\n",
    )
    .unwrap();
    let out_csv = dir.join("out.csv");
    let run = |model: &str| {
        railsim(&[
            "contact",
            "--cases",
            cases.to_str().unwrap(),
            "--out",
            out_csv.to_str().unwrap(),
            "--model",
            model,
        ])
    };
    let (code, out, err) = run("polach");
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("case b (right wheel, y_ws = 6.685 mm): no height carries the load")
            && !err.contains("case a"),
        "{err}"
    );
    assert!(out.contains("1 case(s) do not carry their load"), "{out}");
    let (code, out, err) = run("stripes");
    assert_eq!(code, 0, "{err}");
    assert!(
        !err.contains("warning") && !out.contains("do not carry"),
        "{err} {out}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_input_exits_2_with_a_message() {
    let (code, _, err) = railsim(&["contact", "--wheel", "/nonexistent/wheel.prw"]);
    assert_eq!(code, 2);
    assert!(err.starts_with("railsim: /nonexistent/wheel.prw:"), "{err}");
    let (code, _, err) = railsim(&["contact", "--z-mm", "-7"]);
    assert_eq!(code, 2);
    assert!(err.contains("absurd penetration"), "{err}");
    let (code, _, err) = railsim(&["contact", "--model", "exact"]);
    assert_eq!(code, 2);
    assert!(err.contains("exact"), "{err}");
    // a gauge far from the wheelset's: the profiles' lateral spans show why nothing touches
    let (code, _, err) = railsim(&["contact", "--gauge-mm", "1000"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("spans 695.0 to 810.0 mm and the rail's 499.3 to 573.7 mm")
            && err.contains("check the gauge"),
        "{err}"
    );
}

/// Option values a fuzzing run found to hang, to give non-finite results or to be taken in the
/// wrong unit: each is refused with the option, the range and what was found.
#[test]
fn out_of_range_options_are_refused_before_any_work() {
    for (args, needle) in [
        (
            &["--threads", "100000", "conicity"][..],
            "--threads: expected 0 (one per core) to 256, found 100000",
        ),
        (
            &["contact", "--shear-modulus-gpa", "1e30"][..],
            "--shear-modulus-gpa: expected a number from 1 to 1000, found 1e30",
        ),
        (
            &["contact", "--spin-rad-s=1e30"][..],
            "--spin-rad-s: expected a number from",
        ),
        (
            &["contact", "--speed-m-s", "1e-9"][..],
            "--speed-m-s: expected a number from 0.001 to 200",
        ),
        (
            &["contact", "--inclination", "2:40"][..],
            "--inclination: expected 1:N with N from 5 to 1000, or 0, found \"2:40\"",
        ),
        (
            &["contact", "--inclination", "1:1e-9"][..],
            "--inclination: expected 1:N with N from 5 to 1000",
        ),
        (
            &["modes", "--speed-kmh", "100", "--step-um", "1e-12"][..],
            "--step-um: expected a number from 0.1 to 250, found 1e-12",
        ),
        // above 250 µm the step check's four-times step would fail silently (stop 45)
        (
            &["modes", "--speed-kmh", "100", "--step-um", "500"][..],
            "--step-um: expected a number from 0.1 to 250, found 500",
        ),
        (
            &[
                "modes",
                "--speed-kmh",
                "280",
                "--animate",
                "1",
                "--out",
                "m.txt",
            ][..],
            "--out m.txt: expected a file name ending in .mcap, found extension \"txt\"",
        ),
        (
            &["contact", "--cases", "c.csv", "--out", "x.txt"][..],
            "--out x.txt: expected a file name ending in .csv, found extension \"txt\"",
        ),
        (
            &["contact", "--out", "x.txt"][..],
            "--out x.txt: expected a file name ending in .csv or .json, found extension \"txt\"",
        ),
        (
            &["critical-speed", "--png", "branch.jpg"][..],
            "--png branch.jpg: expected a file name ending in .png, found extension \"jpg\"",
        ),
        (
            &["modes", "--csv", "modes.png"][..],
            "--csv modes.png: expected a file name ending in .csv, found extension \"png\"",
        ),
        (
            &["critical-speed", "--csv", "branch"][..],
            "--csv branch: expected a file name ending in .csv, found no extension",
        ),
        (
            &["curving", "--csv", "table.txt"][..],
            "--csv table.txt: expected a file name ending in .csv, found extension \"txt\"",
        ),
        (
            &["modes", "--speed-kmh", "1e-9"][..],
            "--speed-kmh: expected a number from 0.01 to 1500",
        ),
        (
            &["curving", "--speed-kmh", "1e9"][..],
            "--speed-kmh: expected a number from 0.01 to 1500, found 1e9",
        ),
        (
            &["critical-speed", "--method", "linear", "--tol", "1e-300"][..],
            "--tol: expected a number from 1e-4 to 0.5, found 1e-300",
        ),
        (
            &["critical-speed", "--from-kmh", "1e9"][..],
            "--from-kmh: expected a number from 0.01 to 1500, found 1e9",
        ),
        (
            &[
                "run",
                "scenes/free_wheelset_klingel.toml",
                "--duration-s",
                "1e4",
            ][..],
            "--duration-s 10000: the scene ends after",
        ),
        (
            &["run", "--out", "run.toml"][..],
            "--out run.toml: expected a file name ending in .mcap, found extension \"toml\"",
        ),
        (
            &["critical-speed", "--out", "ramp.csv"][..],
            "--out ramp.csv: expected a file name ending in .mcap",
        ),
        (
            &["contact", "--model", "polach", "--tangential", "exact"][..],
            "--tangential applies only to --model stripes or halfspace",
        ),
        (
            &[
                "contact", "--cases", "c.csv", "--out", "x.csv", "--y-mm", "5",
            ][..],
            "cannot be used with",
        ),
    ] {
        let (code, _, err) = railsim(args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn conicity_reports_the_check_value() {
    let (code, out, err) = railsim(&["conicity", "--amplitudes-mm", "3"]);
    assert_eq!(code, 0, "{err}");
    // The amplitude table comes after the Δr table, which also has a 3.00 row.
    let line = out
        .lines()
        .rfind(|l| l.trim_start().starts_with("3.00"))
        .unwrap();
    let lambda: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    assert!((lambda - 0.185).abs() < 0.01, "{line}");
}

/// Amplitudes and friction are checked before anything is printed: an error leaves standard
/// output empty.
#[test]
fn conicity_checks_the_amplitudes_before_printing() {
    for (option, value, want) in [
        (
            "--amplitudes-mm",
            "3,50",
            "expected amplitudes up to 9.9 mm, found 50",
        ),
        (
            "--amplitudes-mm",
            "3,1e300",
            "expected amplitudes up to 9.9 mm, found 1e300",
        ),
        (
            "--amplitudes-mm",
            "3,0",
            "expected a positive number, found 0",
        ),
        (
            "--mu",
            "-1",
            "mu = -1: expected a friction coefficient from 0.01 to 1",
        ),
    ] {
        let (code, out, err) = railsim(&["conicity", option, value]);
        assert_eq!(code, 2, "{value}: {err}");
        assert!(err.contains(want), "{value}: {err}");
        assert!(out.is_empty(), "{value}: printed before the error:\n{out}");
    }
}

/// The flange angle of S1002 (its 70° flank) and Nadal's limit at the flank's friction.
#[test]
fn conicity_reports_the_flange_angle_and_nadals_limit() {
    for (args, mu) in [
        (&["conicity"][..], 0.3),
        (&["conicity", "--mu", "0.36"][..], 0.36),
        // friction by contact angle: the value at 70°, beyond the table's last angle
        (
            &["conicity", "--friction-by-angle", "10:0.3,60:0.5"][..],
            0.5,
        ),
    ] {
        let (code, out, err) = railsim(args);
        assert_eq!(code, 0, "{err}");
        let line = out
            .lines()
            .find(|l| l.starts_with("flange angle "))
            .unwrap_or_else(|| panic!("no flange angle in\n{out}"));
        let number = |after: &str| -> f64 {
            let rest = &line[line.find(after).unwrap() + after.len()..];
            let end = rest.find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'));
            rest[..end.unwrap_or(rest.len())].parse().unwrap()
        };
        let angle = number("flange angle ");
        assert!((angle - 70.0).abs() < 0.02, "{line}");
        assert!(line.contains(&format!("at μ = {mu}:")), "{line}");
        // Nadal: (tan δ - μ) / (1 + μ tan δ); 1.20 at μ = 0.36, 0.95 at 0.5 (vehicle reference)
        let t = angle.to_radians().tan();
        let want = (t - mu) / (1.0 + mu * t);
        assert!((number(": ") - want).abs() < 1e-3, "{line}");
    }
    // S1002's flange dimensions (contact-theory note §5.1): Sh 28.00, Sd 32.50, qR 10.79 mm;
    // Sd from the flange back the options give
    for (args, sd) in [
        (&["conicity"][..], 32.50),
        (&["conicity", "--flange-back-y-mm", "-71"][..], 33.50),
    ] {
        let (code, out, err) = railsim(args);
        assert_eq!(code, 0, "{err}");
        let line = out
            .lines()
            .find(|l| l.starts_with("flange dimensions: "))
            .unwrap_or_else(|| panic!("no flange dimensions in\n{out}"));
        for want in [
            "Sh 28.00 mm (tip at S = -55.00 mm)".to_string(),
            format!("Sd {sd:.2} mm"),
            "qR 10.79 mm".to_string(),
        ] {
            assert!(line.contains(&want), "{want} not in {line}");
        }
    }
    // a 1:20 cone has no flange: said, and no limit
    let cone = std::env::temp_dir().join(format!("railsim-cone-{}.txt", std::process::id()));
    let table: String = (0..=100)
        .map(|i| format!("{} {}\n", -60 + i, 0.05 * f64::from(-60 + i)))
        .collect();
    std::fs::write(&cone, table).unwrap();
    let (code, out, err) = railsim(&["conicity", "--wheel", cone.to_str().unwrap()]);
    std::fs::remove_file(&cone).ok();
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("no flange angle: the wheel profile has no flank of 45° to 90°"),
        "{out}"
    );
    assert!(!out.contains("Nadal"), "{out}");
    assert!(out.contains("no flange dimensions: "), "{out}");
}

/// An error whose text already ends with its cause is printed once, not twice
/// (`railsim run --out DIR.mcap`, a directory).
#[test]
fn an_error_prints_its_cause_once() {
    // a directory with a log's name
    let dir = std::env::temp_dir().join(format!("railsim-cause-{}.mcap", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (code, _, err) = railsim(&[
        "run",
        "scenes/free_wheelset_klingel.toml",
        "--duration-s",
        "0.01",
        "--out",
        dir.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 2, "{err}");
    let line = err.lines().last().unwrap();
    assert!(line.contains("creating the log"), "{err}");
    assert_eq!(line.matches("os error").count(), 1, "{line}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `railsim critical-speed`: a short ramp that stays above the critical speed writes its half
/// cycles and exits 1 saying the vehicle still hunts at the end; bad settings exit 2 naming the
/// option. (The study's physics: `railsim-sim/tests/stability.rs`.)
#[test]
fn critical_speed_reports_a_ramp_that_ends_while_hunting_and_rejects_bad_settings() {
    let dir = common::temp_dir("cli", "critical");
    let csv = dir.join("branch.csv");
    let png = dir.join("branch.png");
    // the shipped study scene with `polach` (five times cheaper than its `stripes`)
    let scene = common::polach_copy(&dir, "manchester_hunting.toml");
    let (code, out, err) = railsim(&[
        "critical-speed",
        scene.to_str().unwrap(),
        "--png",
        png.to_str().unwrap(),
        "--from-kmh",
        "400",
        "--to-kmh",
        "390",
        "--settle-m",
        "150",
        "--ramp-m",
        "300",
        "--quiet",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{out}\n{err}");
    assert!(out.contains("still hunting"), "{out}");
    assert!(
        out.contains("large hunting (half waves of 0.5 mm or more) during the ramp down to"),
        "{out}"
    );
    assert!(out.contains("bifurcation diagram drawn to"), "{out}");
    // the columns carry the vehicle file's wheelset names, from the front
    assert!(
        out.contains("speed band km/h     ws1 mm   ws2 mm   ws3 mm   ws4 mm  ΣY rms/limit"),
        "{out}"
    );
    assert!(
        out.contains("EN 14363 track-shift force criterion (band-passed"),
        "{out}"
    );
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("wheelset,t_s,speed_kmh,amplitude_mm"));
    // four wheelsets hunting at about 5 Hz by the end of 4 s (the rear bogie's start at rest
    // and grow into it): many half waves each, the last four all above 1 mm
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    for n in 0..4 {
        let w: Vec<&Vec<f64>> = rows.iter().filter(|r| r[0] == n as f64).collect();
        assert!(w.len() >= 20, "wheelset {n}: {} half waves", w.len());
        assert!(
            w[w.len() - 4..].iter().all(|r| r[3] > 1.0 && r[2] < 400.0),
            "wheelset {n}: {:?}",
            &w[w.len() - 4..]
        );
    }
    for (args, want) in [
        (
            vec!["--to-kmh", "500"],
            "--to-kmh (500) must be below --from-kmh",
        ),
        (vec!["--ramp-m=-1"], "--ramp-m: expected a positive number"),
        (vec!["--offset-mm", "0"], "--offset-mm: expected a non-zero"),
        (vec!["--offset-mm", "30"], "lateral offset must lie in"),
    ] {
        let mut a = vec!["critical-speed", "--quiet"];
        a.extend(args);
        let (code, _, err) = railsim(&a);
        assert_eq!(code, 2, "{a:?}: {err}");
        assert!(err.contains(want), "{a:?}: {err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `railsim curving`: one short case of the shipped study scene with `polach` prints its table
/// and writes one CSV row per wheelset; bad settings exit 2 naming the option. (The study's
/// physics: `railsim-sim/tests/curving.rs`.)
#[test]
fn curving_tabulates_a_case_and_rejects_bad_settings() {
    let dir = common::temp_dir("cli", "curving");
    let csv = dir.join("curving.csv");
    let scene = common::polach_copy(&dir, "manchester_curving.toml");
    let (code, out, err) = railsim(&[
        "curving",
        scene.to_str().unwrap(),
        "--radius-m",
        "400",
        "--cant-mm",
        "50",
        "--speed-kmh",
        "70",
        "--direction",
        "right",
        "--transition-m",
        "40",
        "--settle-m",
        "40",
        "--average-m",
        "30",
        "--quiet",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(
        out.contains("R = 400 m, cant 50 mm, 70 km/h: uncompensated"),
        "{out}"
    );
    assert!(out.contains("Y/Q outer"), "{out}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(head[0], "radius_m");
    assert!(head.contains(&"angle_of_attack_mrad") && head.contains(&"wear_right_n"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 4);
    for (n, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), head.len());
        assert_eq!((r[0], r[3], r[6]), ("400", "right", n.to_string().as_str()));
        // the vehicle file's name of the wheelset numbered n from the front
        assert_eq!(r[7], format!("ws{}", n + 1));
    }
    assert!(out.contains("  0 ws1  "), "{out}");
    // a right curve: the leading wheelset runs out to the left (+y)
    let lateral: f64 = rows[0][8].parse().unwrap();
    assert!(lateral > 3.0, "{lateral}");
    for (args, want) in [
        (
            vec!["--radius-m", "0"],
            "--radius-m: expected positive numbers",
        ),
        (vec!["--radius-m", "20"], "the radius must be at least"),
        (
            vec!["--radius-m", "300,600", "--cant-mm", "1,2,3"],
            "--cant-mm: expected one value or one per radius (2), found 3",
        ),
        (
            vec!["--settle-m=-1"],
            "--settle-m: expected a number of metres",
        ),
    ] {
        let mut a = vec!["curving", "--quiet"];
        a.extend(args);
        let (code, _, err) = railsim(&a);
        assert_eq!(code, 2, "{a:?}: {err}");
        assert!(err.contains(want), "{a:?}: {err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A divergent (growing, non-oscillatory) mode, made with a synthetic negative lateral stiffness
/// of 200 MN/m (a force table) on the Wickens wheelset: `railsim modes` warns of it where its
/// list leaves real modes out and marks it `DIVERGENT` with `--all`; the linear critical-speed
/// search, which counts oscillatory modes only, says so in its error.
#[test]
fn a_divergent_mode_is_reported_by_modes_and_the_linear_search() {
    let dir = common::temp_dir("cli", "divergent");
    let root = common::root();
    let vehicle = std::fs::read_to_string(root.join("vehicles/wheelset_springs.toml")).unwrap()
        + "\n[[force]]\nname = \"negative\"\ntype = \"table\"\nbody1 = \"track\"\nbody2 = \"ws\"\n\
           point_m = [0.0, 0.0, 0.46]\ndirection = \"y\"\ndeflection_mm = [0, 10]\n\
           force_n = [0, -2000000]\n";
    std::fs::write(dir.join("v.toml"), vehicle).unwrap();
    let track = root.join("tracks/straight.toml");
    let scene_text = std::fs::read_to_string(root.join("scenes/wheelset_springs_critical.toml"))
        .unwrap()
        .replace("\"../vehicles/wheelset_springs.toml\"", "\"v.toml\"")
        .replace("\"../tracks/straight.toml\"", &format!("{:?}", track));
    assert!(scene_text.contains("\"v.toml\""));
    let scene = dir.join("s.toml");
    std::fs::write(&scene, scene_text).unwrap();
    let scene = scene.to_str().unwrap();
    let (code, out, err) = railsim(&["modes", scene, "--speed-kmh", "100"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("warning: a non-oscillatory mode diverges: Re λ +")
            && out.contains("(ws.y 1.00"),
        "{out}"
    );
    let (code, out, err) = railsim(&["modes", scene, "--speed-kmh", "100", "--all"]);
    assert_eq!(code, 0, "{err}");
    let line = out.lines().find(|l| l.ends_with("DIVERGENT")).unwrap_or("");
    assert!(line.contains("ws.y 1.00"), "{out}");
    assert!(!out.contains("warning"), "{out}");
    let (code, _, err) = railsim(&[
        "critical-speed",
        scene,
        "--method",
        "linear",
        "--from-kmh",
        "300",
        "--to-kmh",
        "100",
        "--scan",
        "2",
        "--quiet",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("note: a non-oscillatory mode diverges at 100.00 km/h"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `railsim modes` and `railsim critical-speed --method linear` on the Wickens wheelset
/// (`scenes/wheelset_springs_critical.toml`, linear creep): the modes table marks the hunting
/// mode unstable above the critical speed, the linear method finds it (301.7 m/s, as the
/// library test) with its step check, and writes its analyses; bad settings exit 2 naming the
/// option. (The method's physics: `railsim-sim/tests/modal.rs`.)
#[test]
fn modes_and_the_linear_critical_speed_of_the_wickens_wheelset() {
    let dir = common::temp_dir("cli", "modes");
    let scene = common::root().join("scenes/wheelset_springs_critical.toml");
    let scene = scene.to_str().unwrap();
    let csv = dir.join("modes.csv");
    let png = dir.join("locus.png");
    let (code, out, err) = railsim(&[
        "modes",
        scene,
        "--speed-kmh",
        "1000,1100",
        "--csv",
        csv.to_str().unwrap(),
        "--png",
        png.to_str().unwrap(),
        "--count",
        "3",
    ]);
    assert_eq!(code, 0, "{err}");
    let (below, above) = out.split_once("1100.0 km/h").expect("two speeds");
    assert!(below.contains("1000.0 km/h: 11 states"), "{out}");
    assert!(!below.contains("UNSTABLE"), "{out}");
    let first = above.lines().nth(2).unwrap();
    assert!(
        first.contains("ws.y 1.00") && first.ends_with("UNSTABLE"),
        "{out}"
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(
        text.starts_with("speed_kmh,frequency_hz,damping_ratio,re_per_s,im_rad_s,coordinates\n")
    );
    assert!(text.lines().count() > 8, "{text}");
    assert!(out.contains("root locus drawn to"), "{out}");
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    // the hunting mode's animation, and a mode number beyond the list
    let anim = dir.join("mode.mcap");
    let (code, out, err) = railsim(&[
        "modes",
        scene,
        "--speed-kmh",
        "1100",
        "--count",
        "2",
        "--animate",
        "1",
        "--out",
        anim.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("mode 1 (") && out.contains("animated at 1100 km/h"),
        "{out}"
    );
    let (code, out, _) = railsim(&["replay", anim.to_str().unwrap()]);
    assert_eq!(code, 0);
    assert!(
        out.contains("/bodies/ws") && out.contains("mode 30."),
        "{out}"
    );
    let (code, _, err) = railsim(&[
        "modes",
        scene,
        "--speed-kmh",
        "1100",
        "--count",
        "2",
        "--animate",
        "3",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--animate: expected a mode number from 1 to 2"),
        "{err}"
    );
    let scan = dir.join("scan.csv");
    let (code, out, err) = railsim(&[
        "critical-speed",
        scene,
        "--method",
        "linear",
        "--to-kmh",
        "1000",
        "--from-kmh",
        "1150",
        "--quiet",
        "--csv",
        scan.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let line = out
        .lines()
        .find(|l| l.starts_with("linear critical speed"))
        .unwrap_or_else(|| panic!("{out}"));
    let v: f64 = line
        .split("): ")
        .nth(1)
        .and_then(|r| r.split(" km/h").next())
        .and_then(|x| x.trim().parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert!((v / 3.6 / 301.73 - 1.0).abs() < 0.003, "{line}");
    assert!(out.contains("check with 4x the difference steps"), "{out}");
    assert!(!out.contains("warning"), "{out}");
    assert!(
        std::fs::read_to_string(&scan)
            .unwrap()
            .starts_with("speed_kmh,least_damped_re_per_s\n")
    );
    for (args, want) in [
        (
            vec!["modes", scene, "--speed-kmh=-5"],
            "--speed-kmh: expected a number from 0.01 to 1500, found -5",
        ),
        (
            vec!["modes", scene, "--step-um", "0"],
            "--step-um: expected a number",
        ),
        (
            vec!["critical-speed", scene, "--method", "linear", "--scan", "0"],
            "--scan: expected at least one",
        ),
        (
            vec![
                "critical-speed",
                scene,
                "--method",
                "linear",
                "--to-kmh",
                "100",
                "--from-kmh",
                "200",
            ],
            "search higher",
        ),
    ] {
        let (code, _, err) = railsim(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `railsim curving --method quasi-static`: a case solved directly prints its table and the
/// solution's iterations; a case without a steady state exits 2 pointing to the time
/// integration. (The method against the time integration: `railsim-sim/tests/curving.rs`.)
#[test]
fn curving_quasi_static_solves_a_case_and_reports_one_without_a_steady_state() {
    let scene = common::root().join("scenes/manchester_curving.toml");
    let scene = scene.to_str().unwrap();
    let base = [
        "curving",
        scene,
        "--method",
        "quasi-static",
        "--model",
        "polach",
        "--radius-m",
        "600",
    ];
    let (code, out, err) = railsim(&base);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("R 600 m, 80 km/h: quasi-static solution")
            && out.contains("Newton iterations"),
        "{out}"
    );
    assert!(out.contains("Y/Q outer"), "{out}");
    // R = 150 m at 120 km/h, 6.7 m/s² uncompensated: no steady state, said, and the case after
    // it (R = 600 m) still solved and printed; exit code 2
    let mut args = base.to_vec();
    args[7] = "150,600";
    args.extend(["--speed-kmh", "120"]);
    let (code, out, err) = railsim(&args);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("R 150 m, 120 km/h: failed: "), "{err}");
    assert!(err.contains("time integration"), "{err}");
    assert!(err.contains("1 of 2 case(s) failed"), "{err}");
    assert!(
        out.contains("R 600 m, 120 km/h: quasi-static solution") && !out.contains("R 150 m, 120"),
        "{out}"
    );
}

/// Several curving cases share the threads case by case: the table is the same, in the same
/// order, as on one thread (quasi-static `polach`, three radii; the wall times of the Newton
/// solutions are left out of the comparison).
#[test]
fn curving_cases_in_parallel_give_the_same_table_in_order() {
    let scene = common::root().join("scenes/manchester_curving.toml");
    let table = |threads: &str| {
        let (code, out, err) = railsim(&[
            "--threads",
            threads,
            "curving",
            scene.to_str().unwrap(),
            "--method",
            "quasi-static",
            "--model",
            "polach",
            "--radius-m",
            "1200,600,900",
            "--cant-mm",
            "100",
        ]);
        assert_eq!(code, 0, "{err}");
        out.lines()
            .map(|l| {
                l.split(", largest scaled residual")
                    .next()
                    .unwrap()
                    .to_owned()
            })
            .collect::<Vec<_>>()
    };
    let (one, two) = (table("1"), table("2"));
    assert_eq!(one, two);
    let order: Vec<&String> = one.iter().filter(|l| l.starts_with("R = ")).collect();
    assert_eq!(order.len(), 3, "{one:?}");
    for (l, r) in order.iter().zip(["R = 1200 m", "R = 600 m", "R = 900 m"]) {
        assert!(l.starts_with(r), "{l}");
    }
}

/// `railsim modes --radius-m`: the modes about steady curving, and what it cannot do.
#[test]
fn modes_in_a_curve_are_listed_and_bad_curves_rejected() {
    let (code, out, err) = railsim(&[
        "modes",
        "--model",
        "polach",
        "--speed-kmh",
        "80",
        "--radius-m",
        "600",
        "--cant-mm",
        "100",
        "--count",
        "3",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("steady curving in R = 600 m with 100 mm cant"),
        "{err}"
    );
    assert!(out.contains("80.0 km/h: 78 states"), "{out}");
    for (args, text) in [
        (vec!["--radius-m=-5"], "expected a positive radius"),
        (
            vec!["--radius-m", "600", "--animate", "1"],
            "straight track only",
        ),
        (vec!["--cant-mm", "100"], "a cant needs a curve"),
    ] {
        let mut all = vec!["modes", "--model", "polach", "--speed-kmh", "80"];
        all.extend(args);
        let (code, _, err) = railsim(&all);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(text), "{err}");
    }
    // the linear critical speed about a (very wide) curve, and the other methods refusing one
    let (code, out, err) = railsim(&[
        "critical-speed",
        "--method",
        "linear",
        "--model",
        "polach",
        "--radius-m",
        "1000000",
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("steady curving in R = 1000000 m"), "{err}");
    assert!(out.contains("linear critical speed"), "{out}");
    let (code, _, err) = railsim(&["critical-speed", "--method", "bisect", "--radius-m", "600"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("only the linear method"), "{err}");
}

/// `--friction-by-angle` lowers the friction on the flange (a lubricated gauge face): the
/// right wheel's flange patch at y = 6.5 mm, in full slip, carries |Ft| = 0.2 Fn instead of
/// 0.3 Fn; a malformed table is refused with the item it could not read.
#[test]
fn friction_by_angle_lubricates_the_flange() {
    let dir = common::temp_dir("cli", "varfric");
    let cases = dir.join("cases.csv");
    std::fs::write(
        &cases,
        "case,side,y_ws_mm,yaw_ws_rad,roll_ws_rad,vpitch_rad_s,fz_target_N\n\
         b,right,6.5,0.0156,-0.004376,-4.3293718,10000\n",
    )
    .unwrap();
    // |Ft| / Fn of the patch with the steepest contact angle
    let flange_ratio = |extra: &[&str]| -> f64 {
        let out = dir.join("out.csv");
        let mut args = vec![
            "contact",
            "--cases",
            cases.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (code, _, err) = railsim(&args);
        assert_eq!(code, 0, "{err}");
        let text = std::fs::read_to_string(&out).unwrap();
        let f = |l: &str, i: usize| -> f64 { l.split(',').nth(i).unwrap().parse().unwrap() };
        // columns: case,side,icp,z_ws_mm,ycp_r_mm,delttr_rad,pen_mm,fn_N,fx_N,fs_N
        let flange = text
            .lines()
            .skip(1)
            .max_by(|a, b| f(a, 5).abs().total_cmp(&f(b, 5).abs()))
            .unwrap()
            .to_owned();
        assert!(f(&flange, 5).abs() > 20f64.to_radians(), "{flange}");
        f(&flange, 8).hypot(f(&flange, 9)) / f(&flange, 7)
    };
    let dry = flange_ratio(&[]);
    let lubricated = flange_ratio(&["--friction-by-angle", "10:0.3,20:0.2"]);
    // (1 % above μ allowed: the strips' tangential forces, each in its own plane, add a little
    // to the patch's normal force and the patch's plane differs from theirs; 0.30026 measured)
    assert!((0.25..=0.303).contains(&dry), "{dry}");
    assert!((0.15..=0.202).contains(&lubricated), "{lubricated}");
    let (code, _, err) = railsim(&["contact", "--friction-by-angle", "10:0.3,20"]);
    assert_ne!(code, 0);
    assert!(
        err.contains("--friction-by-angle: item 2 is \"20\"; expected angle_deg:mu"),
        "{err}"
    );
    let (code, _, err) = railsim(&["contact", "--friction-by-angle", "20:0.3,10:0.2"]);
    assert_ne!(code, 0);
    assert!(err.contains("strictly increasing contact angles"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `railsim contact --friction-ratio-at-infinite-slip --friction-decay-s-per-m`: friction
/// falling with the slip velocity, with `polach`, `fastsim` and `stripes` (FaStrip and FASTSIM
/// per strip). A wheel spinning at twice its rolling speed (100 % creepage, slip velocity
/// 20 m/s) transmits the sliding friction: μ·Fz with Coulomb friction, A·μ·Fz once the
/// friction has fallen (A = 0.4, B = 5 s/m: e^(−100) of the fall left), each within 1 % of the
/// load's share (the patches' normals lean a little from the vertical). The options are
/// refused with `linear` (no friction), `halfspace` and the exact tangential solution (the
/// reference levels); `--polach-*` with another model than `polach`, and out of range.
#[test]
fn falling_friction_on_one_wheel() {
    let fx = |extra: &[&str]| -> f64 {
        let mut args = vec!["contact", "--spin-rad-s", "86.96"];
        args.extend_from_slice(extra);
        let (code, out, err) = railsim(&args);
        assert_eq!(code, 0, "{err}");
        let line = out
            .lines()
            .find(|l| l.starts_with("total force on the wheel"))
            .unwrap_or_else(|| panic!("{out}"));
        // "... Fx = 3001.1 N, ..."
        line.split("Fx = ")
            .nth(1)
            .unwrap()
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    let falling = [
        "--friction-ratio-at-infinite-slip",
        "0.4",
        "--friction-decay-s-per-m",
        "5",
    ];
    for model in [
        &["--model", "polach"][..],
        &["--model", "fastsim"],
        &["--model", "stripes"],
        &["--model", "stripes", "--tangential", "fastsim"],
    ] {
        let coulomb = fx(model);
        let fallen = fx(&[model, &falling[..]].concat());
        eprintln!(
            "{model:?}: Fx at 100 % creepage: Coulomb {coulomb} N, fallen friction {fallen} N"
        );
        assert!((coulomb.abs() - 3000.0).abs() < 30.0, "{coulomb}");
        assert!((fallen.abs() - 1200.0).abs() < 12.0, "{fallen}");
    }
    for (args, want) in [
        (&["--model", "linear"][..], "linear has no friction"),
        (&["--model", "halfspace"], "halfspace, a reference level"),
        (
            &["--model", "stripes", "--tangential", "exact"],
            "the exact tangential solution, a reference level",
        ),
    ] {
        let all = [&["contact"][..], args, &falling[..]].concat();
        let (code, _, err) = railsim(&all);
        assert_ne!(code, 0, "{all:?}");
        assert!(err.contains(want), "{all:?}: {err}");
    }
    let (code, _, err) = railsim(&["contact", "--friction-ratio-at-infinite-slip", "1.5"]);
    assert_ne!(code, 0);
    assert!(
        err.contains("friction ratio at infinite slip A = 1.5: expected a ratio in [0, 1]"),
        "{err}"
    );
    let (code, _, err) = railsim(&["contact", "--polach-k-s", "0.5"]);
    assert_ne!(code, 0);
    assert!(err.contains("apply only to --model polach"), "{err}");
    let (code, _, err) = railsim(&[
        "contact",
        "--model",
        "polach",
        "--polach-k-a",
        "0.3",
        "--polach-k-s",
        "0.4",
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains("polach k_s = 0.4: expected a factor in (0, k_a]"),
        "{err}"
    );
}

/// An output path that names one of the command's inputs is refused before anything is
/// written: the case table and the profile stay as they were.
#[test]
fn an_output_that_would_overwrite_an_input_is_refused() {
    let dir = std::env::temp_dir().join(format!("railsim-cli-overwrite-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases = dir.join("cases.csv");
    let text =
        "side,y_ws_mm,yaw_ws_rad,roll_ws_rad,vpitch_rad_s,fz_target_N\nright,0,0,0,-4.348,10000\n";
    std::fs::write(&cases, text).unwrap();
    let c = cases.to_str().unwrap();
    let (code, _, err) = railsim(&["contact", "--cases", c, "--out", c]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("this is an input of the command") && err.contains("cases.csv"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&cases).unwrap(), text);
    // a case table that names a column twice
    let dup = dir.join("dup.csv");
    std::fs::write(
        &dup,
        "side,y_ws_mm,yaw_ws_rad,roll_ws_rad,vpitch_rad_s,Y_WS_MM,fz_target_N\nright,0,0,0,-4.348,5,10000\n",
    )
    .unwrap();
    let out = dir.join("out.csv");
    let (code, _, err) = railsim(&[
        "contact",
        "--cases",
        dup.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("column 'Y_WS_MM' appears twice (again as column 6)"),
        "{err}"
    );
    // a spin in the wrong unit
    let fast = dir.join("fast.csv");
    std::fs::write(
        &fast,
        "side,y_ws_mm,yaw_ws_rad,roll_ws_rad,vpitch_rad_s,fz_target_N\nright,0,0,0,-1e9,10000\n",
    )
    .unwrap();
    let (code, _, err) = railsim(&[
        "contact",
        "--cases",
        fast.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("case 1: vpitch_rad_s = -1e9 is implausible"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A wheel profile with one point 80 mm off its outline (a robustness sweep's mutation) leaves
/// no facing pairs although the profiles' spans overlap: the message points at the profile's
/// points, not at the gauge.
#[test]
fn a_spike_in_a_profile_is_suspected_when_the_spans_overlap() {
    let dir = std::env::temp_dir().join(format!("railsim-cli-spike-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text = std::fs::read_to_string(root.join("vehicles/profiles/MBench_S1002_v3.prw")).unwrap();
    let spiked = text.replacen(
        "-2.1799520E+01\t-3.4340920E-01",
        "-2.1799520E+01\t80.118",
        1,
    );
    assert_ne!(spiked, text, "the point to move is in the file");
    let wheel = dir.join("spike.prw");
    std::fs::write(&wheel, spiked).unwrap();
    let (code, _, err) = railsim(&["contact", "--wheel", wheel.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(
            "the spans overlap, so check the profiles' points for one far off the outline"
        ),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Negative numbers are option values in every subcommand: a negative friction coefficient or
/// step reaches the option's range check (it was clap's "unexpected argument '-0' found"); the
/// contact's friction range is the scene files' (it accepted up to 2); millimetre options are
/// checked in millimetres under their own names.
#[test]
fn negative_numbers_reach_the_range_checks() {
    for (args, needle) in [
        (
            vec!["contact", "--mu", "-0.1"],
            "friction coefficient from 0.01 to 1",
        ),
        (
            vec!["contact", "--mu", "1.5"],
            "friction coefficient from 0.01 to 1",
        ),
        (
            vec!["contact", "--step-mm", "-1"],
            "--step-mm: expected a number from 0.001 to 5",
        ),
        // the pair's millimetre options in their own units and names (the library's check
        // said "option gauge = 0.001435 m: expected a track gauge from 0.6 to 2 m")
        (
            vec!["contact", "--gauge-mm", "1.435"],
            "--gauge-mm: expected a number from 600 to 2000, found 1.435",
        ),
        (
            vec!["conicity", "--r0-mm", "0.46"],
            "--r0-mm: expected a number from 100 to 1000",
        ),
        (
            vec!["contact", "--y-mm", "500"],
            "--y-mm: expected a number from -100 to 100",
        ),
    ] {
        let (code, _, err) = railsim(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            err.contains(needle) && !err.contains("unexpected argument"),
            "{args:?}: {err}"
        );
    }
}

/// `critical-speed --method linear` prints each analysis' residual and notes a state that is no
/// equilibrium, with the reason: the Manchester vehicle with 5 kN·m of traction on every axle is
/// balanced by Newton on the whole state (its creep forces carried by the suspension to the
/// frozen carbody x: no note, a residual below 1e-5), but with its carbody's x free nothing holds
/// the 43 kN of traction, Newton fails and the note says so (6.0 m/s² on an axle's x); without
/// the torque there is no note.
#[test]
fn the_linear_critical_speed_notes_a_state_that_is_no_equilibrium() {
    let dir = common::temp_dir("cli", "residual");
    let vehicle = common::vehicle_text("manchester_vehicle1.toml")
        .replace("[[wheelset]]\n", "[[wheelset]]\ntorque_nm = 5000\n");
    assert_eq!(vehicle.matches("torque_nm = 5000").count(), 4);
    let driven = dir.join("driven.toml");
    std::fs::write(&driven, vehicle).unwrap();
    let plain = common::polach_copy(&dir, "manchester_hunting.toml");
    let text = std::fs::read_to_string(&plain).unwrap();
    let vehicle_line = text
        .lines()
        .find(|l| l.starts_with("vehicle = "))
        .unwrap()
        .to_owned();
    let scene = dir.join("driven_scene.toml");
    std::fs::write(
        &scene,
        text.replace(
            &vehicle_line,
            &format!("vehicle = \"{}\"", driven.display()),
        ),
    )
    .unwrap();
    let args = |s: &std::path::Path| {
        vec![
            "critical-speed".to_owned(),
            s.to_str().unwrap().to_owned(),
            "--method".to_owned(),
            "linear".to_owned(),
            "--from-kmh".to_owned(),
            "300".to_owned(),
            "--to-kmh".to_owned(),
            "200".to_owned(),
        ]
    };
    let run = |a: Vec<String>| railsim(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let (code, _, err) = run(args(&scene));
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("is not an equilibrium"), "{err}");
    // every analysis' residual, e.g. "; residual 5.1e-7 (d/dt ws1.spin)", is small
    let residuals: Vec<f64> = err
        .split("; residual ")
        .skip(1)
        .map(|r| r.split_whitespace().next().unwrap().parse().unwrap())
        .collect();
    assert!(residuals.len() >= 8, "{err}");
    assert!(residuals.iter().all(|r| *r < 1e-5), "{residuals:?}");
    let free = dir.join("driven_free_scene.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    assert!(text.contains("freeze = [\"carbody.x\"]\n"));
    std::fs::write(&free, text.replace("freeze = [\"carbody.x\"]\n", "")).unwrap();
    let (_, _, err) = run(args(&free));
    assert!(
        err.contains("note: at 200.00 km/h the state linearised about is not an equilibrium")
            && err.contains("(d/dt ws1.x) (Newton on the whole state: "),
        "{err}"
    );
    let (_, _, err) = run(args(&plain));
    assert!(err.contains("; residual "), "{err}");
    assert!(!err.contains("is not an equilibrium"), "{err}");
}

/// `railsim statics`: the built-in vehicle's static wheel loads balance its weight, and on a
/// twist of 3 ‰ its wheels unload as the library's solve on the same rail heights says, in a
/// pattern antisymmetric front to back and left to right (the worst wheel at an end wheelset);
/// a twist of the other sign mirrors it. Bad options, and a twist for a single wheelset, are
/// refused with exit code 2.
#[test]
fn statics_reports_the_wheel_loads_and_their_unloading_on_a_twist() {
    let (code, out, err) = railsim(&["statics", "--twist-permille", "3", "--elements"]);
    assert_eq!(code, 0, "{err}");
    eprintln!("{out}");
    let v = railsim_vehicle::VehicleModel::from_file(
        common::root().join("vehicles/manchester_vehicle1.toml"),
    )
    .unwrap();
    let level = v.static_equilibrium().unwrap();
    let weight = v.total_mass() * v.gravity();
    assert!(out.contains(&format!(
        "sum {:.3} kN against the weight {:.3} kN\n",
        level.total_wheel_load() * 1e-3,
        weight * 1e-3
    )));
    assert!(out.contains("primary_ws1_l"), "{out}");
    // the library's solve on the rail heights of a uniform 3 ‰ twist about the middle of the
    // end wheelsets (x = 0 on this symmetric vehicle)
    let mid = 0.0;
    let heights: Vec<[f64; 2]> = v
        .wheelsets()
        .iter()
        .map(|w| {
            let c = 3e-3 * (w.position[0] - mid);
            [c / 2.0, -c / 2.0]
        })
        .collect();
    let twisted = v.static_equilibrium_on(&heights).unwrap();
    for (w, (q, q0)) in v
        .wheelsets()
        .iter()
        .zip(twisted.wheel_loads.iter().zip(&level.wheel_loads))
    {
        let line = format!(
            "  {:<12} left Q {:8.3} kN (ΔQ/Q0 {:+.3}), right Q {:8.3} kN (ΔQ/Q0 {:+.3})",
            w.name,
            q[0] * 1e-3,
            (q0[0] - q[0]) / q0[0],
            q[1] * 1e-3,
            (q0[1] - q[1]) / q0[1]
        );
        assert!(out.contains(&line), "{line}\n{out}");
    }
    // the front wheelset's right wheel unloads as the rear's left one
    let (front, rear) = (&twisted.wheel_loads[0], &twisted.wheel_loads[3]);
    assert!(
        (front[1] - rear[0]).abs() < 1e-6 * weight,
        "{front:?} {rear:?}"
    );
    assert!(front[1] < level.wheel_loads[0][1]);
    let worst = (level.wheel_loads[0][1] - front[1]) / level.wheel_loads[0][1];
    assert!(
        out.contains(&format!("largest unloading ΔQ/Q0 = {worst:.3}"))
            && out.contains("limit 0.6: within"),
        "{out}"
    );
    // the other sign mirrors it: the front wheelset's left wheel unloads now
    let (_, mirrored, _) = railsim(&["statics", "--twist-permille", "-3"]);
    assert!(
        mirrored.contains(&format!("largest unloading ΔQ/Q0 = {worst:.3}")),
        "{mirrored}"
    );
    let ws1 = mirrored
        .lines()
        .find(|l| l.starts_with("  ws1 ") && l.contains("left Q"))
        .unwrap();
    assert!(
        ws1.contains(&format!(
            "left Q {:8.3} kN (ΔQ/Q0 {worst:+.3})",
            front[1] * 1e-3
        )),
        "{ws1}"
    );
    let (code, out, err) = railsim(&["statics", "--twist-permille", "3", "--limit", "0.2"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("limit 0.2: EXCEEDED"), "{out}");
    // the Manchester vehicle with its first wheelset held in roll
    let dir = common::temp_dir("cli", "statics");
    let held = dir.join("held.toml");
    let text = common::vehicle_text("manchester_vehicle1.toml").replacen(
        "[[wheelset]]\n",
        "[[wheelset]]\nfrozen = [\"roll\"]\n",
        1,
    );
    std::fs::write(&held, text).unwrap();
    for (args, needle) in [
        (
            vec!["statics", "--twist-permille", "100"],
            "--twist-permille: expected a number from -50 to 50, found 100",
        ),
        (
            vec!["statics", "--limit", "0"],
            "--limit: expected a wheel unloading ΔQ/Q0 in (0, 1], found 0",
        ),
        (
            vec![
                "statics",
                "vehicles/wheelset_free.toml",
                "--twist-permille",
                "3",
            ],
            "has no two wheelsets at different x: a uniform twist needs a wheelbase",
        ),
        (
            vec!["statics", held.to_str().unwrap(), "--twist-permille", "3"],
            "wheelset 'ws1' of vehicle 'Manchester benchmark vehicle 1' has its z or roll frozen",
        ),
    ] {
        let (code, _, err) = railsim(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{err}");
    }
}

/// The wheel rows of `railsim statics` on a twist, from the front: each wheelset's name, its
/// wheel loads Q \[kN\] and unloadings ΔQ/Q0, left and right.
fn statics_twist_rows(out: &str) -> Vec<(String, [f64; 2], [f64; 2])> {
    out.lines()
        .filter(|l| l.starts_with("  ") && l.contains(" left Q "))
        .map(|l| {
            let t: Vec<&str> = l.split_whitespace().collect();
            let num = |s: &str| -> f64 { s.trim_end_matches([')', ',']).parse().unwrap() };
            (
                t[0].to_owned(),
                [num(t[3]), num(t[9])],
                [num(t[6]), num(t[12])],
            )
        })
        .collect()
}

/// The wheelsets' cross-levels that `railsim statics --bogie-twist-permille` prints: each
/// wheelset's name, x \[m\] and cross-level \[mm\], from the front.
fn statics_cross_levels(out: &str) -> Vec<(String, f64, f64)> {
    out.lines()
        .filter(|l| l.starts_with("    ") && l.ends_with(" mm"))
        .map(|l| {
            let t: Vec<&str> = l.split_whitespace().collect();
            (
                t[0].to_owned(),
                t[3].parse().unwrap(),
                t[5].parse().unwrap(),
            )
        })
        .collect()
}

/// `railsim statics --twist-permille 0 --bogie-twist-permille 7` on the Manchester vehicle: each
/// bogie twisted alone about its centre (cross-level 7 ‰ · (x − x_b), printed per wheelset),
/// the carbody level; within each bogie the two wheelsets unload opposite wheels by the same
/// ΔQ/Q0 (the front one its right wheel, the left rail being up at the front), and the two
/// bogies, twisted alike, unload alike.
#[test]
fn statics_twists_each_bogie_alone_about_its_centre() {
    let (code, out, err) = railsim(&[
        "statics",
        "--twist-permille",
        "0",
        "--bogie-twist-permille",
        "7",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("on a twist of 0 ‰ over the bogie-centre distance (about x = 0.000 m) and 7 ‰ over each bogie's wheelbase"),
        "{out}"
    );
    let v = railsim_vehicle::VehicleModel::from_file(
        common::root().join("vehicles/manchester_vehicle1.toml"),
    )
    .unwrap();
    let frame_x = |name: &str| v.body(v.body_id(name).unwrap()).position[0];
    for (name, x) in [
        ("bogie_front", frame_x("bogie_front")),
        ("bogie_rear", frame_x("bogie_rear")),
    ] {
        assert!(
            out.contains(&format!(
                "  bogie {name:<12} x = {x:7.3} m:   +0.000 mm at its centre"
            )),
            "{out}"
        );
    }
    let cross = statics_cross_levels(&out);
    let names: Vec<&str> = cross.iter().map(|c| c.0.as_str()).collect();
    assert_eq!(names, ["ws1", "ws2", "ws3", "ws4"], "{out}");
    for (name, x, c) in &cross {
        let w = v.wheelset(v.wheelset_id(name).unwrap());
        assert_eq!(*x, (w.position[0] * 1e3).round() / 1e3);
        let xb = frame_x(if w.position[0] > 0.0 {
            "bogie_front"
        } else {
            "bogie_rear"
        });
        let expected = 7.0 * (w.position[0] - xb);
        assert!(
            (c - expected).abs() <= 0.5e-3 + 1e-9,
            "{name}: {c} mm against {expected} mm"
        );
    }
    let rows = statics_twist_rows(&out);
    let names: Vec<&str> = rows.iter().map(|r| r.0.as_str()).collect();
    assert_eq!(names, ["ws1", "ws2", "ws3", "ws4"], "{out}");
    let du: Vec<[f64; 2]> = rows.iter().map(|r| r.2).collect();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-3 + 1e-9;
    for (front, rear) in [(0, 1), (2, 3)] {
        // the front wheelset's right wheel unloads, the rear's left one, by the same amount
        assert!(du[front][1] > 0.1 && du[rear][0] > 0.1, "{out}");
        assert!(close(du[front][1], du[rear][0]), "{out}");
        assert!(close(du[front][0], du[rear][1]), "{out}");
        for d in [du[front], du[rear]] {
            assert!(close(d[0], -d[1]), "{out}");
        }
    }
    // the carbody level: both bogies alike
    assert!(
        close(du[0][1], du[2][1]) && close(du[1][0], du[3][0]),
        "{out}"
    );
}

/// `railsim statics --twist-permille 3 --bogie-twist-permille 7`: the printed wheel loads are
/// the library's solve on the rail heights of c = 3 ‰ · (x_b − x̄_b) + 7 ‰ · (x − x_b), built
/// here from the vehicle's bogie frames (x_b = ±9.5 m, x̄_b = 0).
#[test]
fn statics_combined_twist_loads_are_the_librarys_on_the_same_rail_heights() {
    let (code, out, err) = railsim(&[
        "statics",
        "--twist-permille",
        "3",
        "--bogie-twist-permille",
        "7",
    ]);
    assert_eq!(code, 0, "{err}");
    let v = railsim_vehicle::VehicleModel::from_file(
        common::root().join("vehicles/manchester_vehicle1.toml"),
    )
    .unwrap();
    let level = v.static_equilibrium().unwrap();
    let frames: Vec<f64> = ["bogie_front", "bogie_rear"]
        .iter()
        .map(|n| v.body(v.body_id(n).unwrap()).position[0])
        .collect();
    let mid = 0.5 * (frames[0] + frames[1]);
    let heights: Vec<[f64; 2]> = v
        .wheelsets()
        .iter()
        .map(|w| {
            let x = w.position[0];
            let xb = if (x - frames[0]).abs() < (x - frames[1]).abs() {
                frames[0]
            } else {
                frames[1]
            };
            let c = 3e-3 * (xb - mid) + 7e-3 * (x - xb);
            [c / 2.0, -c / 2.0]
        })
        .collect();
    let twisted = v.static_equilibrium_on(&heights).unwrap();
    let mut worst: f64 = 0.0;
    for (w, (q, q0)) in v
        .wheelsets()
        .iter()
        .zip(twisted.wheel_loads.iter().zip(&level.wheel_loads))
    {
        let u = [(q0[0] - q[0]) / q0[0], (q0[1] - q[1]) / q0[1]];
        worst = worst.max(u[0]).max(u[1]);
        let line = format!(
            "  {:<12} left Q {:8.3} kN (ΔQ/Q0 {:+.3}), right Q {:8.3} kN (ΔQ/Q0 {:+.3})",
            w.name,
            q[0] * 1e-3,
            u[0],
            q[1] * 1e-3,
            u[1]
        );
        assert!(out.contains(&line), "{line}\n{out}");
    }
    assert!(
        out.contains(&format!("largest unloading ΔQ/Q0 = {worst:.3}")),
        "{out}"
    );
    // the end wheelsets' cross-level: 3 ‰ · 9.5 m + 7 ‰ · 1.28 m
    assert!(
        out.contains("    ws1          x =  10.780 m:  +37.460 mm\n"),
        "{out}"
    );
}

/// With the same twist over the bogie-centre distance and over the bogies' wheelbases,
/// c = G (x − x̄_b): the uniform twist G about x̄_b, which is `--twist-permille G` alone wherever
/// x̄_b equals x̄, the middle of the end wheelsets (on the Manchester vehicle, symmetric fore and
/// aft): the same wheel loads to the printed precision.
#[test]
fn statics_equal_bogie_and_carbody_twists_are_the_uniform_twist() {
    let (code, combined, err) = railsim(&[
        "statics",
        "--twist-permille",
        "3",
        "--bogie-twist-permille",
        "3",
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, uniform, err) = railsim(&["statics", "--twist-permille", "3"]);
    assert_eq!(code, 0, "{err}");
    let rows = |out: &str| -> Vec<String> {
        out.lines()
            .filter(|l| l.contains(" left Q ") || l.starts_with("largest unloading"))
            .map(str::to_owned)
            .collect()
    };
    let (a, b) = (rows(&combined), rows(&uniform));
    assert_eq!(a.len(), 5, "{combined}");
    assert_eq!(a, b, "{combined}\n{uniform}");
    // and the same cross-levels at the end wheelsets as the uniform twist's header
    assert!(
        uniform.contains("(cross-level +32.34 mm at the front wheelset, -32.34 mm at the rear)")
            && combined.contains("    ws1          x =  10.780 m:  +32.340 mm\n")
            && combined.contains("    ws4          x = -10.780 m:  -32.340 mm\n"),
        "{combined}"
    );
}

/// `--bogie-twist-permille` needs bogies: refused (exit code 2, naming the option and the
/// vehicle) for a vehicle without rigid bodies, for the lone bogie of bogie_two_axle.toml (its
/// frame is the heaviest body, the carbody), for a frame left with one wheelset (a 500 kg body
/// at x = 8.22 m over ws2 takes it from bogie_front by the nearest-frame rule; accepted when
/// only the carbody is twisted, G+ = 0), with a carbody twist on a vehicle whose only bogie
/// frame sits at one x, and out of range.
#[test]
fn statics_bogie_twist_needs_bogies_with_a_wheelbase() {
    let dir = common::temp_dir("cli", "statics_bogies");
    let absolute = |file: &str, extra: &str| {
        let path = dir.join(file);
        std::fs::write(&path, common::vehicle_text(file) + extra).unwrap();
        path
    };
    let motor = absolute(
        "manchester_vehicle1.toml",
        "\n[[body]]\nname = \"motor_front\"\nmass_kg = 500\ninertia_kgm2 = [50, 50, 50]\n\
         position_m = [8.22, 0.0, 0.6]\n\n[[force]]\nname = \"motor_mount\"\ntype = \"bushing\"\n\
         body1 = \"bogie_front\"\nbody2 = \"motor_front\"\npoint_m = [8.5, 0.0, 0.6]\n\
         stiffness_n_per_m = [1e7, 1e7, 1e7]\nrotational_stiffness_nm_per_rad = [1e6, 1e6, 1e6]\n",
    );
    // bogie_two_axle.toml under a heavier body 1 m behind: its frame becomes the only bogie
    let ballast = absolute(
        "bogie_two_axle.toml",
        "\n[[body]]\nname = \"ballast\"\nmass_kg = 5000\ninertia_kgm2 = [500, 500, 500]\n\
         position_m = [-1.0, 0.0, 1.0]\n\n[[force]]\nname = \"ballast_mount\"\ntype = \"bushing\"\n\
         body1 = \"bogie\"\nbody2 = \"ballast\"\npoint_m = [-1.0, 0.0, 0.8]\n\
         stiffness_n_per_m = [1e7, 1e7, 1e7]\nrotational_stiffness_nm_per_rad = [1e6, 1e6, 1e6]\n",
    );
    let (motor, ballast) = (motor.to_str().unwrap(), ballast.to_str().unwrap());
    // the lone bogie twisted over its wheelbase alone is fine
    let (code, out, err) = railsim(&["statics", ballast, "--bogie-twist-permille", "7"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("  bogie bogie        x =   0.000 m:"), "{out}");
    // a bogie left with one wheelset needs no wheelbase when only the carbody twist is asked for
    let (code, out, err) = railsim(&[
        "statics",
        motor,
        "--twist-permille",
        "3",
        "--bogie-twist-permille",
        "0",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("largest unloading ΔQ/Q0"), "{out}");
    for (args, needle) in [
        (
            vec![
                "statics",
                "vehicles/wheelset_springs.toml",
                "--bogie-twist-permille",
                "7",
            ],
            "--bogie-twist-permille: vehicle 'wheelset on lateral and yaw springs (Wickens case, §2.2)' has no bogie frame: expected a carbody (the heaviest rigid body) and bogie frames (other rigid bodies at least 0.5 m in x from its centre, as in the run's assessment), found no rigid body",
        ),
        (
            vec![
                "statics",
                "vehicles/bogie_two_axle.toml",
                "--bogie-twist-permille",
                "7",
            ],
            "--bogie-twist-permille: vehicle 'two-axle bogie (Manchester vehicle 1 bogie)' has no bogie frame: expected, besides the carbody 'bogie' (the heaviest rigid body, x = 0.000 m)",
        ),
        (
            vec!["statics", motor, "--bogie-twist-permille", "7"],
            "--bogie-twist-permille: bogie frame 'bogie_front' of vehicle 'Manchester benchmark vehicle 1' has 1 wheelset(s) ('ws1' at x = 10.780 m): a twist over its wheelbase needs two at different x",
        ),
        (
            vec![
                "statics",
                ballast,
                "--twist-permille",
                "3",
                "--bogie-twist-permille",
                "7",
            ],
            "--twist-permille with --bogie-twist-permille: vehicle 'two-axle bogie (Manchester vehicle 1 bogie)' has 1 bogie frame(s) ('bogie' at x = 0.000 m), none at another x",
        ),
        (
            vec!["statics", "--bogie-twist-permille", "60"],
            "--bogie-twist-permille: expected a number from -50 to 50, found 60",
        ),
        (
            vec!["statics", "--bogie-twist-permille", "-50.5"],
            "--bogie-twist-permille: expected a number from -50 to 50, found -50.5",
        ),
    ] {
        let (code, _, err) = railsim(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `railsim modes --all` on the free conical wheelset (`stripes`, 18 km/h): the kinematic
/// oscillation of a free wheelset grows (UNSTABLE); the real roots of its free longitudinal
/// coordinate, an exact zero and its round-off (+1e-4/s), are neutral (before stop 45 the
/// round-off root was printed UNSTABLE; found by the stop's audit).
#[test]
fn modes_calls_a_free_coordinates_round_off_root_neutral() {
    let scene = common::root().join("scenes/free_wheelset_klingel.toml");
    let (code, out, err) = railsim(&[
        "modes",
        scene.to_str().unwrap(),
        "--speed-kmh",
        "18",
        "--all",
    ]);
    assert_eq!(code, 0, "{err}");
    let kinematic = out.lines().find(|l| l.contains("ws.y 1.00")).unwrap();
    assert!(kinematic.ends_with("UNSTABLE"), "{out}");
    let free: Vec<&str> = out.lines().filter(|l| l.contains("ws.x 1.00")).collect();
    assert!(!free.is_empty(), "{out}");
    assert!(free.iter().all(|l| !l.ends_with("UNSTABLE")), "{out}");
    assert!(free.iter().any(|l| l.ends_with("neutral")), "{out}");
}

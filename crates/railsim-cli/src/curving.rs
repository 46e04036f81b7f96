//! `railsim curving [SCENE]`: steady-state curving of a vehicle for a set of curves and speeds
//! (`railsim_sim::curving`, docs/models/dynamics.md "Steady-state curving").

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use rayon::prelude::*;

use railsim_sim::curving::{
    CurveCase, CurvingRun, CurvingSolution, QuasiStatic, SteadyCurving, quasi_static_curving,
    steady_curving,
};
use railsim_sim::{RunOptions, Scene};

/// The built-in scene of the study, from the repository this binary was built in.
pub const DEFAULT_SCENE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenes/manchester_curving.toml"
);

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
pub enum Direction {
    /// The curve's centre on the left.
    Left,
    /// The curve's centre on the right.
    Right,
}

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
pub enum CurvingMethodName {
    /// Run the vehicle into the curve and average once it runs steadily.
    Time,
    /// Solve for the steady state directly (Newton on the whole state): 10-30 times faster,
    /// for curves with a steady state and a contact model smooth enough for Newton.
    QuasiStatic,
}

#[derive(Args)]
pub struct CurvingArgs {
    /// Scene file: its vehicle, track file (rail profiles, gauge, inclination, cant base, rail
    /// support; its alignment and irregularities replaced), contact model, integrator and log
    /// rate are used; default: the built-in scenes/manchester_curving.toml
    pub scene: Option<PathBuf>,
    /// Curve radii (m), comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [300.0, 600.0, 1200.0])]
    pub radius_m: Vec<f64>,
    /// Cant (mm), one value for all curves or one per radius.
    #[arg(long, value_delimiter = ',', default_values_t = [100.0])]
    pub cant_mm: Vec<f64>,
    /// Speeds (km/h), comma-separated: every radius is run at every speed.
    #[arg(long, value_delimiter = ',', default_values_t = [80.0])]
    pub speed_kmh: Vec<f64>,
    /// Side of the curve's centre.
    #[arg(long, value_enum, default_value = "left")]
    pub direction: Direction,
    /// Method: time integration (means over --average-m) or the quasi-static solution.
    #[arg(long, value_enum, default_value = "time")]
    pub method: CurvingMethodName,
    /// Contact model instead of the scene's.
    #[arg(long, value_enum)]
    pub model: Option<crate::ModelName>,
    /// Length of the transition (clothoid and cant ramp) into the curve (m).
    #[arg(long, default_value_t = 80.0)]
    pub transition_m: f64,
    /// Distance the rearmost wheelset runs in the curve before the averaging (m).
    #[arg(long, default_value_t = 100.0)]
    pub settle_m: f64,
    /// Distance over which the means are taken (m).
    #[arg(long, default_value_t = 100.0)]
    pub average_m: f64,
    /// Write one row per case and wheelset as CSV.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// No progress line.
    #[arg(long, short)]
    pub quiet: bool,
}

pub fn run_curving(a: &CurvingArgs) -> Result<ExitCode> {
    // (before the study, which takes minutes)
    if let Some(csv) = &a.csv {
        crate::check_extension("--csv", csv, &["csv"])?;
    }
    let path = a
        .scene
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_SCENE));
    for (name, v) in [
        ("--transition-m", a.transition_m),
        ("--average-m", a.average_m),
    ] {
        if !(v.is_finite() && v > 0.0) {
            bail!("{name}: expected a positive number, found {v}");
        }
    }
    if !(a.settle_m.is_finite() && a.settle_m >= 0.0) {
        bail!(
            "--settle-m: expected a number of metres ≥ 0, found {}",
            a.settle_m
        );
    }
    if let Some(v) = a.radius_m.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        bail!("--radius-m: expected positive numbers, found {v}");
    }
    crate::check_speeds("--speed-kmh", &a.speed_kmh)?;
    if a.cant_mm.len() != 1 && a.cant_mm.len() != a.radius_m.len() {
        bail!(
            "--cant-mm: expected one value or one per radius ({}), found {}",
            a.radius_m.len(),
            a.cant_mm.len()
        );
    }
    let mut scene = Scene::from_file(&path)?;
    if let Some(m) = a.model {
        scene.contact.model = m.into();
    }
    let run = CurvingRun {
        transition: a.transition_m,
        settle: a.settle_m,
        average: a.average_m,
    };
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    eprintln!(
        "railsim curving: {} (contact model {}): {} curve(s) × {} speed(s), transition {} m, means over {} m after {} m in the curve",
        scene.name,
        scene.contact.model.name(),
        a.radius_m.len(),
        a.speed_kmh.len(),
        a.transition_m,
        a.average_m,
        a.settle_m
    );
    let mut cases = Vec::new();
    for (i, &radius) in a.radius_m.iter().enumerate() {
        let cant = a.cant_mm[if a.cant_mm.len() == 1 { 0 } else { i }] * 1e-3;
        for &kmh in &a.speed_kmh {
            let case = CurveCase {
                radius,
                cant,
                left: a.direction == Direction::Left,
                speed: kmh / 3.6,
            };
            cases.push((radius, kmh, case));
        }
    }
    let solve = |case: &CurveCase, progress: &mut dyn FnMut(f64, f64)| match a.method {
        CurvingMethodName::Time => steady_curving(&scene, case, &run, &opts, progress),
        CurvingMethodName::QuasiStatic => {
            quasi_static_curving(&scene, case, &run, &QuasiStatic::default())
        }
    };
    // Several cases share the pool's threads case by case (each case's own right-hand sides then
    // mostly stay on its thread); the progress is a line per finished case. One case, or one
    // thread, runs with the progress line of its time integration.
    let results: Vec<Result<SteadyCurving, _>> =
        if cases.len() > 1 && rayon::current_num_threads() > 1 {
            cases
                .par_iter()
                .map(|(radius, kmh, case)| {
                    let t0 = std::time::Instant::now();
                    let r = solve(case, &mut |_, _| {});
                    if !a.quiet {
                        eprintln!(
                            "R {radius} m, {kmh} km/h: {} in {:.1} s",
                            if r.is_ok() { "solved" } else { "failed" },
                            t0.elapsed().as_secs_f64()
                        );
                    }
                    r
                })
                .collect()
        } else {
            cases
            .iter()
            .map(|(radius, kmh, case)| {
                let mut progress = crate::run::throttled(a.quiet, |t, t_end, w| {
                    eprint!(
                        "\rR {radius} m, {kmh} km/h: t = {t:7.3} / {t_end:.3} s   real {w:7.1} s "
                    );
                });
                let r = solve(case, &mut progress);
                if !a.quiet && a.method == CurvingMethodName::Time {
                    eprintln!();
                }
                r
            })
            .collect()
        };
    // a case that fails is reported and the others go on (before stop 45 the first failure
    // ended the command and the cases after it were lost); any failure makes the exit code 2
    let mut done = Vec::new();
    let mut failed = 0;
    for ((radius, kmh, _), r) in cases.iter().zip(results) {
        let r = match r {
            Ok(r) => r,
            Err(e) => {
                let e = anyhow::Error::from(e);
                eprintln!(
                    "railsim curving: R {radius} m, {kmh} km/h: failed: {}",
                    crate::message(&e)
                );
                failed += 1;
                continue;
            }
        };
        if let CurvingSolution::QuasiStatic {
            iterations,
            residual,
            wall,
        } = r.solution
        {
            outln!(
                "R {radius} m, {kmh} km/h: quasi-static solution, {iterations} Newton iterations, largest scaled residual {residual:.3}, {wall:.2} s"
            );
        }
        print_case(&r)?;
        done.push(r);
    }
    let results = done;
    if let Some(p) = &a.csv
        && !results.is_empty()
    {
        std::fs::write(p, csv(&results)?).with_context(|| format!("writing {}", p.display()))?;
        outln!("cases written to {}", p.display());
    }
    if failed > 0 {
        eprintln!(
            "railsim curving: {failed} of {} case(s) failed (above){}",
            cases.len(),
            if results.is_empty() {
                ""
            } else {
                "; the others are in the table"
            }
        );
        return Ok(ExitCode::from(2));
    }
    // a case in which the vehicle did not settle is reported, and makes the exit code 1
    let unsteady = results
        .iter()
        .any(|r| r.wheelsets.iter().any(|w| w.lateral_swing > UNSTEADY_SWING));
    if unsteady {
        outln!(
            "some wheelset's lateral displacement swung by more than {} mm during the averaging: \
             not a steady state (hunting, or a longer --settle-m needed)",
            UNSTEADY_SWING * 1e3
        );
        return Ok(ExitCode::from(1));
    }
    Ok(ExitCode::SUCCESS)
}

/// \[m\] lateral swing during the averaging above which a case is reported as not steady.
const UNSTEADY_SWING: f64 = 0.5e-3;

/// Outer and inner wheel index (left 0, right 1) of a case.
fn outer_inner(r: &SteadyCurving) -> (usize, usize) {
    if r.case.left { (1, 0) } else { (0, 1) }
}

fn print_case(r: &SteadyCurving) -> Result<()> {
    let c = &r.case;
    let cb = r.carbody_lateral.map_or_else(String::new, |a| {
        format!("; carbody comfort point 0 (its centre by default) reads {a:.3} m/s² laterally")
    });
    outln!(
        "R = {} m, cant {} mm, {} km/h: uncompensated {:.3} m/s² (cant deficiency {:.0} mm){cb}",
        c.radius,
        c.cant * 1e3,
        kmh(c.speed),
        r.uncompensated,
        r.cant_deficiency * 1e3
    );
    // the wheelsets by number from the front and by name in the vehicle file
    let label = |n: usize| match r.wheelset_names.get(n) {
        Some(name) => format!("{n} {name}"),
        None => n.to_string(),
    };
    let width = (0..r.wheelsets.len())
        .map(|n| label(n).chars().count())
        .max()
        .unwrap_or(2)
        .max(9);
    outln!(
        "  {:<width$}  y out mm  AoA out mrad   ΣY out kN  Y outer kN  Q outer kN  Y/Q outer  Y inner kN  Q inner kN  Tγ outer N  Tγ inner N  swing mm",
        "wheelset"
    );
    let (o, i) = outer_inner(r);
    // "out": toward the outside of the curve (−y in a left curve)
    let out = if c.left { -1.0 } else { 1.0 };
    for (n, w) in r.wheelsets.iter().enumerate() {
        outln!(
            "  {:<width$}  {:8.2}  {:12.2}  {:10.2}  {:10.2}  {:10.2}  {:9.3}  {:10.2}  {:10.2}  {:10.1}  {:10.1}  {:8.3}",
            label(n),
            out * w.lateral * 1e3,
            out * w.angle_of_attack * 1e3,
            out * w.sum_y * 1e-3,
            w.wheels[o].y * 1e-3,
            w.wheels[o].q * 1e-3,
            w.wheels[o].y_over_q,
            w.wheels[i].y * 1e-3,
            w.wheels[i].q * 1e-3,
            w.wheels[o].wear,
            w.wheels[i].wear,
            w.lateral_swing * 1e3
        );
    }
    Ok(())
}

/// A text field of a CSV row: quoted (quotes doubled) where it holds a comma, a quote or a line
/// break (RFC 4180), as it is otherwise.
pub(crate) fn csv_field(text: &str) -> std::borrow::Cow<'_, str> {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\"")).into()
    } else {
        text.into()
    }
}

fn csv(results: &[SteadyCurving]) -> Result<String> {
    let mut text = String::from(
        "radius_m,cant_mm,speed_kmh,direction,uncompensated_m_s2,cant_deficiency_mm,wheelset,\
         wheelset_name,lateral_mm,angle_of_attack_mrad,sum_y_kn,y_left_kn,q_left_kn,y_over_q_left,wear_left_n,\
         y_right_kn,q_right_kn,y_over_q_right,wear_right_n,lateral_swing_mm\n",
    );
    for r in results {
        let c = &r.case;
        for (n, w) in r.wheelsets.iter().enumerate() {
            let [l, rt] = &w.wheels;
            writeln!(
                text,
                "{},{},{},{},{:.6},{:.3},{n},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.3},{:.6},{:.6},{:.6},{:.3},{:.6}",
                c.radius,
                c.cant * 1e3,
                kmh(c.speed),
                if c.left { "left" } else { "right" },
                r.uncompensated,
                r.cant_deficiency * 1e3,
                csv_field(r.wheelset_names.get(n).map_or("", String::as_str)),
                w.lateral * 1e3,
                w.angle_of_attack * 1e3,
                w.sum_y * 1e-3,
                l.y * 1e-3,
                l.q * 1e-3,
                l.y_over_q,
                l.wear,
                rt.y * 1e-3,
                rt.q * 1e-3,
                rt.y_over_q,
                rt.wear,
                w.lateral_swing * 1e3
            )?;
        }
    }
    Ok(text)
}

/// \[km/h\] a speed given in km/h and stored in m/s, back to what was given (120, not
/// 120.00000000000001).
fn kmh(v: f64) -> f64 {
    (v * 3.6 * 1e9).round() / 1e9
}

#[cfg(test)]
mod tests {
    use super::csv_field;

    #[test]
    fn a_csv_field_is_quoted_only_where_it_must_be() {
        assert_eq!(csv_field("ws1"), "ws1");
        assert_eq!(csv_field("front, left"), "\"front, left\"");
        assert_eq!(csv_field("the \"lead\""), "\"the \"\"lead\"\"\"");
    }
}

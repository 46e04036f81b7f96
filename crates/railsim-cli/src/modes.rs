//! `railsim modes [SCENE]` and `railsim critical-speed --method linear`: the eigenvalue analysis
//! of a vehicle running centred on straight ideal track (`railsim_sim::modal`).

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use clap::Args;

use railsim_sim::Scene;
use railsim_sim::curving::{CurveCase, CurvingRun, QuasiStatic};
use railsim_sim::modal::{LinearCritical, Linearisation, ModalAnalysis, ModalOptions, Mode};

use crate::chart::{Labels, Series, line_chart};
use crate::critical::{CriticalArgs, DEFAULT_SCENE};

/// The check of a linearisation: the same analysis with the difference steps this many times
/// larger.
const CHECK_FACTOR: f64 = 4.0;
/// \[-\] relative difference of the two critical speeds above which the result is flagged.
const CHECK_TOL: f64 = 0.01;

#[derive(Args)]
pub struct ModesArgs {
    /// Scene file: its vehicle, track file (rail profiles, gauge, inclination, rail support;
    /// the alignment is replaced by a tangent and irregularities removed) and contact model are
    /// used; default: the built-in scenes/manchester_hunting.toml
    pub scene: Option<PathBuf>,
    /// Contact model instead of the scene's.
    #[arg(long, value_enum)]
    pub model: Option<crate::ModelName>,
    /// Speeds (km/h), comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [100.0, 200.0, 300.0])]
    pub speed_kmh: Vec<f64>,
    /// Modes listed per speed, least damped first (oscillatory modes only unless --all).
    #[arg(long, default_value_t = 12)]
    pub count: usize,
    /// List real (non-oscillatory) modes too.
    #[arg(long)]
    pub all: bool,
    /// Difference step of the positions (µm, µrad); rates use ten times it per second.
    #[arg(long, default_value_t = 1.0)]
    pub step_um: f64,
    /// Write every mode at every speed as CSV (speed, frequency, damping ratio, eigenvalue,
    /// leading coordinates).
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Draw a root locus to this PNG: the damping ratio against speed of the --count
    /// oscillatory modes whose damping gets lowest over the speeds, each followed from one
    /// speed to the next by the nearest eigenvalue (give several speeds).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Animate mode number K of the first speed's list (counted from 1) to an MCAP log (--out):
    /// the equilibrium plus the mode's shape oscillating at its frequency.
    #[arg(long, value_name = "K")]
    pub animate: Option<usize>,
    /// The animation's log.
    #[arg(long, default_value = "out/mode.mcap")]
    pub out: PathBuf,
    /// The animation's largest displacement (mm; mrad for a rotation).
    #[arg(long, default_value_t = 5.0)]
    pub amplitude_mm: f64,
    /// The animation's length in periods of the mode.
    #[arg(long, default_value_t = 3.0)]
    pub periods: f64,
    /// The curve to linearise about, if any.
    #[command(flatten)]
    pub curve: CurveArgs,
}

/// A curve to linearise about (`railsim modes`, `railsim critical-speed --method linear`).
#[derive(Args)]
pub struct CurveArgs {
    /// Linearise about steady curving in a curve of this radius (m) instead of centred running
    /// on straight track: the quasi-static curving state (`railsim curving --method
    /// quasi-static`), which needs a Hertz contact model (e.g. --model polach); in
    /// `critical-speed`, with --method linear only.
    #[arg(long)]
    pub radius_m: Option<f64>,
    /// The curve's cant (mm), with --radius-m.
    #[arg(long, default_value_t = 0.0)]
    pub cant_mm: f64,
    /// The curve's direction, with --radius-m.
    #[arg(long, value_enum, default_value_t = crate::curving::Direction::Left)]
    pub direction: crate::curving::Direction,
}

/// What `--radius-m`, `--cant-mm` and `--direction` ask to linearise about.
fn about(curve: &CurveArgs) -> Result<Linearisation> {
    let (cant_mm, direction) = (curve.cant_mm, curve.direction);
    match curve.radius_m {
        None if cant_mm != 0.0 => bail!("--cant-mm {cant_mm}: a cant needs a curve (--radius-m)"),
        None => Ok(Linearisation::Straight),
        Some(r) if r.is_finite() && r > 0.0 && cant_mm.is_finite() && cant_mm >= 0.0 => {
            Ok(Linearisation::Curve {
                case: CurveCase {
                    radius: r,
                    cant: cant_mm * 1e-3,
                    left: direction == crate::curving::Direction::Left,
                    speed: 0.0,
                },
                run: CurvingRun::default(),
                qs: QuasiStatic::default(),
            })
        }
        Some(r) => bail!(
            "--radius-m {r} with --cant-mm {cant_mm}: expected a positive radius and a cant of 0 mm or more"
        ),
    }
}

fn about_text(about: &Linearisation) -> String {
    match about {
        Linearisation::Straight => "its centred running on straight ideal track".to_owned(),
        Linearisation::Curve { case, .. } => format!(
            "its steady curving in R = {} m with {} mm cant",
            case.radius,
            case.cant * 1e3
        ),
    }
}

/// The difference steps of `--step-um`, from 0.1 to 250 µm: below 0.1 µm the differences of
/// the contact forces drown in their round-off (at 1e-12 µm a derivative is NaN, at 1e-9 µm six
/// spurious modes appear); above 250 µm the check that repeats a search at four times the step
/// would exceed the library's 1 mm and fail (before stop 45 `--step-um 500` then gave a result
/// 6.8 % off without the warning); validation §11 checks 0.25 to 64 µm.
pub(crate) fn options(step_um: f64) -> Result<ModalOptions> {
    crate::in_range("--step-um", step_um, 0.1, 250.0)?;
    Ok(ModalOptions {
        position_step: step_um * 1e-6,
        rate_step: step_um * 1e-5,
    })
}

fn shape_text(m: &Mode) -> String {
    m.shape
        .iter()
        .map(|(n, v)| format!("{n} {v:.2}"))
        .collect::<Vec<_>>()
        .join(", ")
}

pub fn run_modes(a: &ModesArgs) -> Result<ExitCode> {
    if let Some(png) = &a.png {
        crate::chart::check_png_name("--png", png)?;
    }
    if let Some(csv) = &a.csv {
        crate::check_extension("--csv", csv, &["csv"])?;
    }
    let path = a
        .scene
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_SCENE));
    if a.speed_kmh.is_empty() {
        bail!("--speed-kmh: give at least one speed");
    }
    crate::check_speeds("--speed-kmh", &a.speed_kmh)?;
    let opts = options(a.step_um)?;
    let mut scene = Scene::from_file(&path)?;
    if let Some(m) = a.model {
        scene.contact.model = m.into();
    }
    let about = about(&a.curve)?;
    if a.animate.is_some() && about != Linearisation::Straight {
        bail!("--animate: animates a mode on straight track only, not with --radius-m");
    }
    if a.animate.is_some() {
        crate::check_extension("--out", &a.out, &["mcap"])?;
    }
    eprintln!(
        "railsim modes: {} (contact model {}): eigenvalues of the vehicle linearised about {}",
        scene.name,
        scene.contact.model.name(),
        about_text(&about)
    );
    let mut csv =
        String::from("speed_kmh,frequency_hz,damping_ratio,re_per_s,im_rad_s,coordinates\n");
    let mut analyses = Vec::new();
    for &kmh in &a.speed_kmh {
        let r = about
            .modes(&scene, kmh / 3.6, &opts)
            .context("railsim modes")?;
        print_modes(&r, a)?;
        for m in &r.modes {
            writeln!(
                csv,
                "{kmh},{:.6},{:.6},{:.6},{:.6},\"{}\"",
                m.frequency,
                m.damping_ratio,
                m.re,
                m.im,
                shape_text(m)
            )?;
        }
        analyses.push(r);
    }
    if let Some(p) = &a.csv {
        std::fs::write(p, csv).with_context(|| format!("writing {}", p.display()))?;
        outln!("modes written to {}", p.display());
    }
    if let Some(k) = a.animate {
        let first = &analyses[0];
        let listed: Vec<&Mode> = first
            .modes
            .iter()
            .filter(|m| a.all || m.is_oscillatory())
            .take(a.count)
            .collect();
        let Some(mode) = k.checked_sub(1).and_then(|i| listed.get(i)) else {
            bail!(
                "--animate: expected a mode number from 1 to {} (the list at {} km/h), found {k}",
                listed.len(),
                a.speed_kmh[0]
            );
        };
        let stats = railsim_sim::modal::animate_mode(
            &scene,
            first,
            mode,
            a.amplitude_mm * 1e-3,
            a.periods,
            &a.out,
        )
        .context("railsim modes")?;
        outln!(
            "mode {k} ({:.3} Hz, {}) animated at {} km/h: {} ({} messages)",
            mode.frequency,
            shape_text(mode),
            a.speed_kmh[0],
            stats.path.display(),
            stats.messages
        );
    }
    if let Some(png) = &a.png {
        let lines = root_locus(&mut analyses, a.count);
        let title = format!(
            "{} ({}): root locus",
            scene.name,
            scene.contact.model.name()
        );
        line_chart(
            png,
            &Labels {
                title: &title,
                x: "speed [km/h]",
                y: "damping ratio [%]",
            },
            &lines,
        )?;
        outln!("root locus drawn to {}", png.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// The damping ratio \[%\] against speed of the oscillatory modes, each followed from speed to
/// speed to the nearest unclaimed eigenvalue (distance in the complex plane relative to the
/// mode's magnitude): the `count` whose smallest damping over the speeds is lowest, named by
/// their frequency and leading coordinate at the highest speed.
fn root_locus(analyses: &mut [ModalAnalysis], count: usize) -> Vec<Series> {
    analyses.sort_by(|p, q| p.speed.total_cmp(&q.speed));
    let Some(first) = analyses.first() else {
        return Vec::new();
    };
    let mut tracks: Vec<(Vec<(f64, f64)>, Mode)> = first
        .modes
        .iter()
        .filter(|m| m.is_oscillatory())
        .map(|m| {
            (
                vec![(first.speed * 3.6, 100.0 * m.damping_ratio)],
                m.clone(),
            )
        })
        .collect();
    for r in &analyses[1..] {
        let mut free: Vec<&Mode> = r.modes.iter().filter(|m| m.is_oscillatory()).collect();
        for (points, last) in &mut tracks {
            let d = |m: &Mode| (m.re - last.re).hypot(m.im - last.im) / last.re.hypot(last.im);
            let Some(k) = (0..free.len()).min_by(|&i, &j| d(free[i]).total_cmp(&d(free[j]))) else {
                continue;
            };
            let m = free.swap_remove(k);
            points.push((r.speed * 3.6, 100.0 * m.damping_ratio));
            *last = m.clone();
        }
    }
    let lowest = |p: &[(f64, f64)]| p.iter().map(|q| q.1).fold(f64::INFINITY, f64::min);
    tracks.sort_by(|p, q| lowest(&p.0).total_cmp(&lowest(&q.0)));
    tracks
        .into_iter()
        .take(count)
        .map(|(points, m)| Series {
            name: format!(
                "{:.2} Hz {}",
                m.frequency,
                m.shape.first().map_or("", |s| s.0.as_str())
            ),
            points,
        })
        .collect()
}

fn print_modes(r: &ModalAnalysis, a: &ModesArgs) -> Result<()> {
    outln!(
        "{:.1} km/h: {} states, {} modes ({} oscillatory); largest residual at the equilibrium {:.2e} ({})",
        r.speed * 3.6,
        r.states,
        r.modes.len(),
        r.modes.iter().filter(|m| m.is_oscillatory()).count(),
        r.residual.1,
        r.residual.0
    );
    match &r.balance {
        Ok(0) => {}
        Ok(n) => outln!(
            "  the equilibrium balanced by Newton on the whole state in {n} iterations (the traction or brake torque's creep forces carried by the suspension)"
        ),
        Err(e) if r.residual.1 > RESIDUAL_NOTE => outln!(
            "  not an equilibrium: Newton on the whole state failed ({e}); the modes describe the motion about a state that drifts"
        ),
        Err(e) => {
            outln!("  Newton on the whole state failed ({e}); the residual above is what is left")
        }
    }
    outln!("  frequency Hz  damping ratio   Re λ 1/s  leading coordinates (relative amplitude)");
    for m in r
        .modes
        .iter()
        .filter(|m| a.all || m.is_oscillatory())
        .take(a.count)
    {
        outln!(
            "  {:12.3}  {:13.4}  {:9.3}  {}{}",
            m.frequency,
            m.damping_ratio,
            m.re,
            shape_text(m),
            // a real root grows only as a divergence; a tiny positive one is the round-off of a
            // free coordinate's zero (before stop 45 it was printed UNSTABLE)
            match m.growth() {
                _ if m.is_divergent() => "  DIVERGENT",
                g if g > 0.0 && m.is_oscillatory() => "  UNSTABLE",
                g if g >= 0.0 => "  neutral",
                _ => "",
            }
        );
    }
    // a growing real mode is an instability even where the list leaves real modes out
    if !a.all
        && let Some(m) = r.divergent()
    {
        outln!(
            "  warning: a non-oscillatory mode diverges: Re λ {:+.4}/s ({}); --all lists it",
            m.re,
            shape_text(m)
        );
    }
    Ok(())
}

/// \[m/s², rad/s²\] the largest acceleration of the state linearised about above which
/// `critical-speed --method linear` notes that it is no equilibrium (the Manchester vehicle's
/// is 1.4e-3; with 5 kN·m of traction per axle 5e-7 once Newton has balanced it, 6.0 on an
/// axle's x where Newton fails because nothing holds the carbody's x).
const RESIDUAL_NOTE: f64 = 0.1;

/// `railsim critical-speed --method linear`.
pub fn linear(a: &CriticalArgs, scene: &Scene) -> Result<ExitCode> {
    let opts = options(a.step_um)?;
    let tol = a.tol.unwrap_or(0.002);
    let (lo, hi) = (a.to_kmh / 3.6, a.from_kmh / 3.6);
    let about = about(&a.curve)?;
    eprintln!(
        "railsim critical-speed: {} (contact model {}): eigenvalues of the vehicle linearised about {} from {} to {} km/h ({} intervals, then bisection to {} %)",
        scene.name,
        scene.contact.model.name(),
        about_text(&about),
        a.to_kmh,
        a.from_kmh,
        a.scan,
        tol * 100.0
    );
    let quiet = a.quiet;
    let mut noted = false;
    let mut progress = |r: &ModalAnalysis| {
        if !quiet && let Some(m) = r.least_stable() {
            eprintln!(
                "  {:7.2} km/h: least damped mode {:.3} Hz, Re λ {:+.4}/s ({}); residual {:.1e} ({})",
                r.speed * 3.6,
                m.frequency,
                m.re,
                m.shape.first().map_or("", |s| s.0.as_str()),
                r.residual.1,
                r.residual.0
            );
        }
        // A linearisation about a state that is not an equilibrium (Newton could not balance
        // a traction torque, say) describes another motion.
        if !noted && r.residual.1 > RESIDUAL_NOTE {
            noted = true;
            let why = match &r.balance {
                Err(e) => format!(" (Newton on the whole state: {e})"),
                Ok(_) => String::new(),
            };
            eprintln!(
                "note: at {:.2} km/h the state linearised about is not an equilibrium: its largest acceleration is {:.2e} ({}){why}; the modes describe the motion about a state that drifts",
                r.speed * 3.6,
                r.residual.1,
                r.residual.0
            );
        }
    };
    let res = railsim_sim::modal::linear_critical_speed_about(
        scene,
        &about,
        &opts,
        (lo, hi),
        a.scan,
        tol,
        &mut progress,
    )
    .context("railsim critical-speed")?;
    // the check: the same search with larger steps (a contact whose forces are not smooth at
    // the steps' scale gives a different answer)
    let check_opts = ModalOptions {
        position_step: CHECK_FACTOR * opts.position_step,
        rate_step: CHECK_FACTOR * opts.rate_step,
    };
    let check = railsim_sim::modal::linear_critical_speed_about(
        scene,
        &about,
        &check_opts,
        (lo, hi),
        a.scan,
        tol,
        &mut |_| {},
    )
    .map(|c| c.critical_speed);
    write_scan(a, scene, &res)?;
    let v = res.critical_speed;
    outln!(
        "unstable mode above it: {:.3} Hz ({})",
        res.mode.frequency,
        shape_text(&res.mode)
    );
    match check {
        Ok(vc) => {
            outln!(
                "check with {CHECK_FACTOR}x the difference steps ({} µm): {:.1} km/h ({:+.2} %)",
                a.step_um * CHECK_FACTOR,
                vc * 3.6,
                100.0 * (vc / v - 1.0)
            );
            if (vc / v - 1.0).abs() > CHECK_TOL {
                outln!(
                    "warning: the two differ by more than {} %: the contact model's forces are not smooth at the steps' scale (STRIPES' strips, docs/validation.md §11); use --model polach or fastsim for eigenvalue analyses, or compare with --method bisect",
                    CHECK_TOL * 100.0
                );
            }
        }
        Err(e) => outln!("check with {CHECK_FACTOR}x the difference steps failed: {e:#}"),
    }
    outln!(
        "linear critical speed (an oscillatory mode loses its damping): {:.1} km/h ({:.2} m/s), {} analyses",
        v * 3.6,
        v,
        res.scan.len()
    );
    if let Some((vd, m)) = &res.divergent {
        outln!(
            "warning: a non-oscillatory mode diverges at {:.2} km/h, the lowest speed analysed at which one does (Re λ {:+.4}/s, {}): an instability without oscillation, which this critical speed does not count",
            vd * 3.6,
            m.re,
            shape_text(m)
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn write_scan(a: &CriticalArgs, scene: &Scene, res: &LinearCritical) -> Result<()> {
    let mut pts: Vec<(f64, f64)> = res.scan.iter().map(|&(v, g)| (v * 3.6, g)).collect();
    pts.sort_by(|p, q| p.0.total_cmp(&q.0));
    if let Some(p) = &a.csv {
        let mut text = String::from("speed_kmh,least_damped_re_per_s\n");
        for (v, g) in &pts {
            writeln!(text, "{v:.4},{g:.6}")?;
        }
        std::fs::write(p, text).with_context(|| format!("writing {}", p.display()))?;
        outln!("analyses written to {}", p.display());
    }
    if let Some(png) = &a.png {
        let title = format!(
            "{} ({}): least damped oscillatory mode",
            scene.name,
            scene.contact.model.name()
        );
        line_chart(
            png,
            &Labels {
                title: &title,
                x: "speed [km/h]",
                y: "Re λ [1/s]",
            },
            &[
                Series {
                    name: "Re λ".into(),
                    points: pts,
                },
                Series {
                    name: "zero".into(),
                    points: vec![(a.to_kmh, 0.0), (a.from_kmh, 0.0)],
                },
            ],
        )?;
        outln!("real parts drawn to {}", png.display());
    }
    Ok(())
}

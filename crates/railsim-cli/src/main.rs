//! `railsim`, the command-line program. The only crate that prints and chooses exit codes:
//! 0 ok, 1 the computation ran but a check failed, 2 usage, input or model error.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, Parser, Subcommand, ValueEnum};

use railsim_contact::contact_format::{ContactRow, parse_cases_csv, solve_case};
use railsim_contact::{
    ContactModelKind, ContactOptions, ContactWorkspace, FallingFriction, Friction, HertzSearch,
    LOAD_RESIDUAL_NOTICE, PairSpec, PatchResult, PolachAdhesion, Side, Tangential,
    WheelRailContact, WheelRailPair, WheelsetPose, WheelsetVelocity,
};
use railsim_contact::{geometry, pair, pose};
use railsim_elastic::Material;
use railsim_profile::conicity::{
    MIN_FLANGE_ANGLE, WheelsetTrackSetup, delta_r_interp, equivalent_conicity_harmonic,
    equivalent_conicity_kinematic, flange_angle, flange_dimensions, nadal_limit,
    rolling_radius_difference_with_jumps,
};
use railsim_profile::{Profile, ProfileKind, analytic, read_simpack, read_table_mm};

/// `println!` to standard output that returns the write error from the enclosing function
/// (which returns `anyhow::Result`) instead of panicking: a closed pipe (`railsim replay LOG |
/// head`) ends the command quietly ([`broken_pipe`]).
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($arg)*) {
            return Err(anyhow::Error::from(e));
        }
    }};
}

mod chart;
mod critical;
mod curving;
mod modes;
mod replay;
mod run;
mod statics;

/// Most threads `--threads` accepts (the wheels of a vehicle are a few dozen evaluations per
/// right-hand side; each thread costs a stack and a start-up).
const MAX_THREADS: usize = 256;

/// railsim: rail-vehicle dynamics with online multi-patch wheel/rail contact.
#[derive(Parser)]
#[command(name = "railsim", version, about)]
struct Cli {
    /// Threads for the wheels' contact evaluations of a simulation (0: one per core; 1: none
    /// besides the main one; at most 256). The results do not depend on it.
    #[arg(long, global = true, default_value_t = 0)]
    threads: usize,
    #[command(subcommand)]
    command: Command,
}

// (Negative numbers are values, not options, in every subcommand: `--mu -0.1` is refused by the
// option's range check, not by clap's "unexpected argument '-0'".)
#[derive(Subcommand)]
enum Command {
    /// Simulate a scene (default: the built-in scene, Manchester vehicle 1 at 55 m/s over
    /// irregular straight track into a curve), with a progress line, an MCAP log and a summary.
    #[command(allow_negative_numbers = true)]
    Run(run::RunArgs),
    /// Evaluate one wheel/rail contact (default: S1002 on UIC60 1:40, gauge 1435 mm, flange-back
    /// 1360 mm, r0 = 460 mm, 10 kN wheel load), or a batch of cases with --cases.
    #[command(allow_negative_numbers = true)]
    Contact(ContactArgs),
    /// Rolling-radius difference, contact angles and equivalent conicity of a wheelset on a track.
    #[command(allow_negative_numbers = true)]
    Conicity(ConicityArgs),
    /// Read a log: list its channels, scene and statistics (no options), export topics and a
    /// time range to CSV (--csv), or plot signals against time to PNG (--plot ... --png).
    #[command(allow_negative_numbers = true)]
    Replay(replay::ReplayArgs),
    /// Hunting (critical) speed of a vehicle on straight track: ramp the speed down from a
    /// hunting limit cycle (default; the nonlinear critical speed), or bisect on the growth rate
    /// of a small disturbance at constant speed (--method bisect), or from the eigenvalues of the
    /// linearised vehicle (--method linear).
    #[command(allow_negative_numbers = true)]
    CriticalSpeed(critical::CriticalArgs),
    /// Modes of the vehicle linearised about its centred running on straight ideal track at
    /// given speeds: frequency, damping ratio, eigenvalue and the coordinates each mode moves.
    #[command(allow_negative_numbers = true)]
    Modes(modes::ModesArgs),
    /// Steady-state curving: run the vehicle into curves of given radius and cant at given
    /// speeds and tabulate the means per wheelset and wheel once it runs steadily (lateral
    /// displacement, angle of attack, Y, Q, Y/Q, ΣY, wear number), or solve for the steady
    /// state directly (--method quasi-static).
    #[command(allow_negative_numbers = true)]
    Curving(curving::CurvingArgs),
    /// A vehicle's static equilibrium on level track (wheel loads, elements' static forces)
    /// and, with --twist-permille or --bogie-twist-permille, its wheels' unloading ΔQ/Q0 on a
    /// twisted track.
    #[command(allow_negative_numbers = true)]
    Statics(statics::StaticsArgs),
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum ModelName {
    Linear,
    Polach,
    Fastsim,
    Stripes,
    Halfspace,
}

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
enum TangentialName {
    Fastrip,
    Fastsim,
    Exact,
}

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
enum HertzSearchName {
    Point,
    Travel,
}

impl From<HertzSearchName> for HertzSearch {
    fn from(h: HertzSearchName) -> Self {
        match h {
            HertzSearchName::Point => HertzSearch::Point,
            HertzSearchName::Travel => HertzSearch::Travel,
        }
    }
}

impl From<TangentialName> for Tangential {
    fn from(t: TangentialName) -> Self {
        match t {
            TangentialName::Fastrip => Tangential::Fastrip,
            TangentialName::Fastsim => Tangential::Fastsim,
            TangentialName::Exact => Tangential::Exact,
        }
    }
}

impl From<ModelName> for ContactModelKind {
    fn from(m: ModelName) -> Self {
        match m {
            ModelName::Linear => ContactModelKind::Linear,
            ModelName::Polach => ContactModelKind::Polach,
            ModelName::Fastsim => ContactModelKind::Fastsim,
            ModelName::Stripes => ContactModelKind::Stripes,
            ModelName::Halfspace => ContactModelKind::Halfspace,
        }
    }
}

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
enum SideName {
    Left,
    Right,
}

/// Wheel, rail, track and material: shared by `contact` and `conicity`.
#[derive(Args, Clone)]
struct PairArgs {
    /// Wheel profile: SIMPACK .prw or a y-z table in mm (z up); default built-in S1002.
    #[arg(long)]
    wheel: Option<PathBuf>,
    /// Rail profile: SIMPACK .prr or a y-z table in mm (z up); default built-in UIC60 (60E1).
    #[arg(long)]
    rail: Option<PathBuf>,
    /// Rail inclination applied to the rail profile, as 1:N with N from 5 to 1000, or 0 (use 0
    /// for a profile file that is already inclined, such as the Manchester benchmark .prr).
    #[arg(long, default_value = "1:40")]
    inclination: String,
    /// Track gauge (mm), measured 14 mm below the top of the rail.
    #[arg(long, default_value_t = 1435.0)]
    gauge_mm: f64,
    /// Flange-back distance (mm).
    #[arg(long, default_value_t = 1360.0)]
    flange_back_mm: f64,
    /// Lateral position of the flange back on the wheel profile (mm).
    #[arg(long, default_value_t = -70.0, allow_hyphen_values = true)]
    flange_back_y_mm: f64,
    /// Nominal rolling radius (mm).
    #[arg(long, default_value_t = 460.0)]
    r0_mm: f64,
    /// Combined shear modulus (GPa), 1 to 1000 (82 GPa with nu = 0.28 is E = 210 GPa).
    #[arg(long, default_value_t = 82.0)]
    shear_modulus_gpa: f64,
    /// Poisson's ratio.
    #[arg(long, default_value_t = 0.28)]
    poisson: f64,
    /// Coulomb friction coefficient.
    #[arg(long, default_value_t = 0.3)]
    mu: f64,
    /// Friction varying with the contact angle instead of `--mu`: `angle_deg:mu` pairs,
    /// angles increasing, linear in between and constant beyond the ends (railsim's contact
    /// angle, positive toward the flange; CONTACT's VARFRC with α = −angle on the right rail),
    /// e.g. `10:0.3,20:0.2` for a gauge face lubricated to 0.2.
    #[arg(long, value_name = "ANGLE_DEG:MU,...")]
    friction_by_angle: Option<String>,
}

#[derive(Args)]
struct ContactArgs {
    #[command(flatten)]
    pair: PairArgs,
    /// Contact model.
    #[arg(long, value_enum, default_value = "stripes")]
    model: ModelName,
    /// Tangential solution of `stripes` (per strip: fastrip, fastsim; or exact: Kalker's
    /// steady-rolling solution on a grid over the patch, the reference level, about a thousand
    /// times slower) and `halfspace` (per grid row: fastrip, fastsim; or exact); default fastrip. The
    /// Hertz models have their own.
    #[arg(long, value_enum)]
    tangential: Option<TangentialName>,
    /// Travelling step of the isosceles pairs inside contact zones (mm), the contact model's
    /// default; narrow zones are refined to at least 12 pairs whatever the step.
    #[arg(long, default_value_t = 1.0)]
    step_mm: f64,
    /// How the Hertz models (linear, polach, fastsim) find their contact points: the
    /// single-point search (bounding hierarchies and Newton on the rigid contact pair) or the
    /// seed's travelling.
    #[arg(long, value_enum, default_value = "point")]
    hertz_search: HertzSearchName,
    /// `polach` only: Polach's reduction factor k_A of the initial slope, in (0, 1] (Polach
    /// 2005; default 1).
    #[arg(long)]
    polach_k_a: Option<f64>,
    /// `polach` only: Polach's reduction factor k_S in the slip area, in (0, k_A] (default 1).
    #[arg(long)]
    polach_k_s: Option<f64>,
    /// `polach`, `fastsim`, `stripes` (FaStrip, FASTSIM): the friction at infinite slip
    /// velocity over `--mu`, A in [0, 1] (default 1: no fall): mu = mu0 ((1 - A) exp(-B w) + A)
    /// at slip velocity w (Polach 2005; per strip with `stripes`).
    #[arg(long)]
    friction_ratio_at_infinite_slip: Option<f64>,
    /// `polach`, `fastsim`, `stripes` (FaStrip, FASTSIM): the rate B (s/m) at which the friction
    /// falls with the slip velocity, in [0, 100] (default 0).
    #[arg(long)]
    friction_decay_s_per_m: Option<f64>,
    /// Which wheel.
    #[arg(long, value_enum, default_value = "left")]
    side: SideName,
    /// Lateral wheelset displacement (mm), positive to the left (track frame).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    y_mm: f64,
    /// Yaw angle (mrad), positive nose to the left.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    yaw_mrad: f64,
    /// Roll angle (mrad) about the track x-axis.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    roll_mrad: f64,
    /// Forward speed (m/s), 0.001 to 200.
    #[arg(long, default_value_t = 20.0, allow_hyphen_values = true)]
    speed_m_s: f64,
    /// Wheelset spin (rad/s); default pure rolling, speed / r0; within ±10 speed / r0.
    #[arg(long, allow_hyphen_values = true)]
    spin_rad_s: Option<f64>,
    /// Vertical wheel load (kN) (the wheelset height is iterated to carry it).
    #[arg(long, conflicts_with = "z_mm", allow_hyphen_values = true)]
    load_kn: Option<f64>,
    /// Vertical wheelset position (mm) (up), instead of a load.
    #[arg(long, allow_hyphen_values = true)]
    z_mm: Option<f64>,
    /// Batch mode: a CSV of cases with CONTACT's column names (side, y_ws_mm, yaw_ws_rad,
    /// roll_ws_rad, vpitch_rad_s, and fz_target_N or z_ws_mm), in CONTACT's conventions.
    #[arg(
        long,
        requires = "out",
        conflicts_with_all = ["side", "y_mm", "yaw_mrad", "roll_mrad", "speed_m_s", "spin_rad_s", "load_kn", "z_mm"]
    )]
    cases: Option<PathBuf>,
    /// Write the results: .csv or .json (batch mode: CSV, one row per case and patch).
    #[arg(long)]
    out: Option<PathBuf>,
}

#[derive(Args)]
struct ConicityArgs {
    #[command(flatten)]
    pair: PairArgs,
    /// Amplitudes at which the equivalent conicity is reported (mm).
    #[arg(long, value_delimiter = ',', default_value = "1,2,3,4,5,6")]
    amplitudes_mm: Vec<f64>,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let command = || match &cli.command {
        Command::Run(a) => run::run_scene(a),
        Command::Contact(a) => run_contact(a),
        Command::Conicity(a) => run_conicity(a),
        Command::Replay(a) => replay::run_replay(a),
        Command::CriticalSpeed(a) => critical::run_critical(a),
        Command::Curving(a) => curving::run_curving(a),
        Command::Modes(a) => modes::run_modes(a),
        Command::Statics(a) => statics::run_statics(a),
    };
    // The command runs on a thread of a rayon pool, so that a simulation's right-hand side
    // shares the wheels' contact evaluations with the pool's other threads
    // (`railsim_sim::dynamics`); with one thread, or if no pool can be made, it runs here.
    if cli.threads > MAX_THREADS {
        eprintln!(
            "railsim: --threads: expected 0 (one per core) to {MAX_THREADS}, found {}",
            cli.threads
        );
        return ExitCode::from(2);
    }
    let result = match cli.threads {
        1 => command(),
        n => match rayon::ThreadPoolBuilder::new().num_threads(n).build() {
            Ok(pool) => pool.install(command),
            Err(_) => command(),
        },
    };
    match result {
        Ok(code) => code,
        Err(e) if broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("railsim: {}", message(&e));
            ExitCode::from(2)
        }
    }
}

/// The error and its causes joined by ": ", each cause left out when the text before it already
/// ends with it (the library errors print their own source, as `LogError::Io` does).
fn message(e: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in e.chain() {
        let c = cause.to_string();
        if text.is_empty() {
            text = c;
        } else if !text.ends_with(&c) {
            text.push_str(": ");
            text.push_str(&c);
        }
    }
    text
}

/// Whether `e` is the standard output closed by its reader (`| head`): not a failure of the
/// command, which ends quietly with success, as Unix tools do.
fn broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// `--inclination`: `1:N` with N from 5 to 1000 (as in a track file's `rail_inclination`), or 0.
fn parse_inclination(s: &str) -> Result<f64> {
    let s = s.trim();
    let bad = || anyhow!("--inclination: expected 1:N with N from 5 to 1000, or 0, found \"{s}\"");
    if let Some((a, b)) = s.split_once(':') {
        let a: f64 = a.trim().parse().map_err(|_| bad())?;
        let b: f64 = b.trim().parse().map_err(|_| bad())?;
        if a != 1.0 || !(b.is_finite() && (5.0..=1000.0).contains(&b)) {
            return Err(bad());
        }
        return Ok((1.0 / b).atan());
    }
    let v: f64 = s.parse().map_err(|_| bad())?;
    if v != 0.0 {
        return Err(bad());
    }
    Ok(0.0)
}

/// Speeds of the studies' option `name` (km/h): the range a scene accepts
/// (`railsim_sim::scene::MIN_SPEED_KMH` to `MAX_SPEED_KMH`).
fn check_speeds(name: &str, speeds: &[f64]) -> Result<()> {
    use railsim_sim::scene::{MAX_SPEED_KMH, MIN_SPEED_KMH};
    for &v in speeds {
        in_range(name, v, MIN_SPEED_KMH, MAX_SPEED_KMH)?;
    }
    Ok(())
}

/// An output file named by `option` must end in one of `allowed` (lower case, without the dot;
/// the case of the file's extension does not matter): the format is chosen by it, and a file
/// with another ending would not be read back as what it holds.
pub(crate) fn check_extension(option: &str, path: &Path, allowed: &[&str]) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if !allowed.contains(&ext.as_str()) {
        let list: Vec<String> = allowed.iter().map(|e| format!(".{e}")).collect();
        let found = if ext.is_empty() {
            "no extension".to_owned()
        } else {
            format!("extension \"{ext}\"")
        };
        bail!(
            "{option} {}: expected a file name ending in {}, found {found}",
            path.display(),
            list.join(" or ")
        );
    }
    Ok(())
}

/// An error if `out`, the output of `option`, is one of the command's `inputs` (writing it
/// would destroy the input). An output that does not exist yet is no input.
pub(crate) fn check_not_input(option: &str, out: &Path, inputs: &[&Path]) -> Result<()> {
    let Ok(o) = out.canonicalize() else {
        return Ok(());
    };
    if let Some(i) = inputs
        .iter()
        .find(|i| i.canonicalize().is_ok_and(|c| c == o))
    {
        bail!(
            "{option} {}: this is an input of the command ({}), which the output would overwrite; expected another file",
            out.display(),
            i.display()
        );
    }
    Ok(())
}

/// `--out` of a command that writes an MCAP log of `scene` (read from `scene_path`): a `.mcap`
/// file that is none of the scene's own files.
pub(crate) fn check_log_out(
    out: &Path,
    scene_path: &Path,
    scene: &railsim_sim::Scene,
) -> Result<()> {
    check_extension("--out", out, &["mcap"])?;
    check_not_input(
        "--out",
        out,
        &[scene_path, &scene.vehicle_file, &scene.track_file],
    )
}

/// `v` if it is finite and within `[lo, hi]`, else an error naming the option and the range.
fn in_range(name: &str, v: f64, lo: f64, hi: f64) -> Result<f64> {
    if !(v.is_finite() && (lo..=hi).contains(&v)) {
        bail!(
            "{name}: expected a number from {} to {}, found {}",
            railsim_profile::short_number(lo),
            railsim_profile::short_number(hi),
            railsim_profile::short_number(v)
        );
    }
    Ok(v)
}

fn load_profile(path: &Path, kind: ProfileKind) -> Result<Profile> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let p = match ext.as_str() {
        "prw" | "prr" => read_simpack(path, kind)?,
        _ => read_table_mm(path, kind)?,
    };
    Ok(p)
}

fn positive(name: &str, v: f64) -> Result<f64> {
    if !(v.is_finite() && v > 0.0) {
        bail!(
            "{name}: expected a positive number, found {}",
            railsim_profile::short_number(v)
        );
    }
    Ok(v)
}

/// `v` \[mm\] if it lies in the range `r` \[m\] (a contact-crate range), else an error in
/// millimetres naming the option: the pair's options in their own units and names (the
/// library would report them in metres under its field names: `--gauge-mm 1.435` gave "option
/// gauge = 0.001435 m: expected a track gauge from 0.6 to 2 m").
fn in_range_mm(name: &str, v: f64, r: (f64, f64)) -> Result<f64> {
    in_range(name, v, r.0 * 1e3, r.1 * 1e3)
}
fn r0_mm(a: &PairArgs) -> Result<f64> {
    in_range_mm("--r0-mm", a.r0_mm, pair::R0_RANGE)
}
fn flange_back_mm(a: &PairArgs) -> Result<f64> {
    in_range_mm(
        "--flange-back-mm",
        a.flange_back_mm,
        pair::FLANGE_BACK_DISTANCE_RANGE,
    )
}
fn flange_back_y_mm(a: &PairArgs) -> Result<f64> {
    in_range_mm(
        "--flange-back-y-mm",
        a.flange_back_y_mm,
        pair::FLANGE_BACK_Y_RANGE,
    )
}
fn gauge_mm(a: &PairArgs) -> Result<f64> {
    in_range_mm("--gauge-mm", a.gauge_mm, pair::GAUGE_RANGE)
}

/// The wheel and rail profiles of the arguments, built-in S1002 and UIC60 by default.
fn profiles(a: &PairArgs) -> Result<(Profile, Profile)> {
    let wheel = match &a.wheel {
        Some(p) => load_profile(p, ProfileKind::Wheel)?,
        None => analytic::s1002(),
    };
    let rail = match &a.rail {
        Some(p) => load_profile(p, ProfileKind::Rail)?,
        None => analytic::uic60(),
    };
    Ok((wheel, rail))
}

fn build_pair(a: &PairArgs) -> Result<WheelRailPair> {
    let (wheel, rail) = profiles(a)?;
    let material = Material::new(
        // (steel 80 GPa; beyond these the value is a unit error)
        in_range("--shear-modulus-gpa", a.shear_modulus_gpa, 1.0, 1000.0)? * 1e9,
        a.poisson,
    )
    .map_err(|e| anyhow!("material: {e}"))?;
    let spec = PairSpec {
        wheel,
        rail,
        r0: r0_mm(a)? * 1e-3,
        flange_back_distance: flange_back_mm(a)? * 1e-3,
        flange_back_y: flange_back_y_mm(a)? * 1e-3,
        gauge: gauge_mm(a)? * 1e-3,
        gauge_depth: 0.014,
        inclination: parse_inclination(&a.inclination)?,
        material,
        friction: friction(a)?,
        curve_ds: 5e-5,
        smoothing: 0.0,
    };
    Ok(WheelRailPair::new(&spec)?)
}

/// The friction of the arguments: `--friction-by-angle` if given, else `--mu` (unchecked:
/// [`Friction::check`]).
fn friction(a: &PairArgs) -> Result<Friction> {
    match &a.friction_by_angle {
        None => Ok(Friction::Constant(a.mu)),
        Some(text) => parse_friction_by_angle(text),
    }
}

/// `--friction-by-angle`: `angle_deg:mu` pairs separated by commas.
fn parse_friction_by_angle(text: &str) -> Result<Friction> {
    let (mut angle, mut mu) = (Vec::new(), Vec::new());
    for (i, item) in text.split(',').enumerate() {
        let parsed = item.split_once(':').and_then(|(a, m)| {
            Some((a.trim().parse::<f64>().ok()?, m.trim().parse::<f64>().ok()?))
        });
        let Some((a, m)) = parsed else {
            bail!(
                "--friction-by-angle: item {} is {:?}; expected angle_deg:mu, e.g. 10:0.3",
                i + 1,
                item
            );
        };
        angle.push(a.to_radians());
        mu.push(m);
    }
    let f = Friction::ByContactAngle { angle, mu };
    f.check()
        .map_err(|e| anyhow!("--friction-by-angle {text:?}: {e}"))?;
    Ok(f)
}

fn run_contact(a: &ContactArgs) -> Result<ExitCode> {
    if let Some(out) = &a.out {
        if a.cases.is_some() {
            check_extension("--out", out, &["csv"])?;
        } else {
            check_extension("--out", out, &["csv", "json"])?;
        }
        let inputs = [&a.cases, &a.pair.wheel, &a.pair.rail];
        let inputs: Vec<&Path> = inputs.into_iter().flatten().map(PathBuf::as_path).collect();
        check_not_input("--out", out, &inputs)?;
    }
    if a.tangential.is_some() && !matches!(a.model, ModelName::Stripes | ModelName::Halfspace) {
        bail!(
            "--tangential applies only to --model stripes or halfspace (the Hertz models have their own tangential solution)"
        );
    }
    let polach_flags = [a.polach_k_a, a.polach_k_s];
    if polach_flags.iter().any(Option::is_some) && !matches!(a.model, ModelName::Polach) {
        bail!(
            "--polach-* options apply only to --model polach (Polach's extended creep-force model)"
        );
    }
    let falling_flags = [a.friction_ratio_at_infinite_slip, a.friction_decay_s_per_m];
    if falling_flags.iter().any(Option::is_some)
        && matches!(a.model, ModelName::Linear | ModelName::Halfspace)
    {
        bail!(
            "--friction-ratio-at-infinite-slip and --friction-decay-s-per-m apply to --model polach, fastsim or stripes (linear has no friction; halfspace, a reference level, takes Coulomb friction)"
        );
    }
    let d = PolachAdhesion::default();
    let polach = PolachAdhesion {
        k_a: a.polach_k_a.unwrap_or(d.k_a),
        k_s: a.polach_k_s.unwrap_or(d.k_s),
    };
    let f = FallingFriction::default();
    let falling_friction = FallingFriction {
        ratio: a.friction_ratio_at_infinite_slip.unwrap_or(f.ratio),
        decay: in_range(
            "--friction-decay-s-per-m",
            a.friction_decay_s_per_m.unwrap_or(f.decay),
            0.0,
            100.0,
        )?,
    };
    let pair = build_pair(&a.pair)?;
    let mut opts = ContactOptions {
        model: a.model.into(),
        tangential: a.tangential.unwrap_or(TangentialName::Fastrip).into(),
        hertz_search: a.hertz_search.into(),
        polach,
        falling_friction,
        ..Default::default()
    };
    opts.travel.step = in_range_mm("--step-mm", a.step_mm, geometry::STEP_RANGE)? * 1e-3;
    opts.travel.max_step = opts.travel.max_step.max(opts.travel.step);
    let contact = WheelRailContact::new(pair, opts)?;
    let mut ws = ContactWorkspace::new();
    if let Some(cases) = &a.cases {
        return run_batch(
            &contact,
            cases,
            a.out.as_deref().expect("clap requires --out"),
            &mut ws,
        );
    }
    let side = match a.side {
        SideName::Left => Side::Left,
        SideName::Right => Side::Right,
    };
    let r0 = contact.pair.r0;
    // (the contact's creepages divide by the speed: a wheelset at rest has none)
    let vx = in_range("--speed-m-s", a.speed_m_s, 1e-3, 200.0)?;
    // a longitudinal creepage within ±9 (a locked or a spinning wheel is ±1)
    let spin = match a.spin_rad_s {
        Some(w) => in_range("--spin-rad-s", w, -10.0 * vx / r0, 10.0 * vx / r0)?,
        None => vx / r0,
    };
    let vel = WheelsetVelocity {
        vx,
        spin,
        ..Default::default()
    };
    let mut pose = WheelsetPose {
        y: in_range_mm("--y-mm", a.y_mm, (-pose::MAX_LATERAL, pose::MAX_LATERAL))? * 1e-3,
        z: a.z_mm.unwrap_or(0.0) * 1e-3,
        roll: a.roll_mrad * 1e-3,
        yaw: a.yaw_mrad * 1e-3,
    };
    let summary = if a.z_mm.is_some() {
        contact.evaluate(side, &pose, &vel, &mut ws)?
    } else {
        let load = a.load_kn.unwrap_or(10.0);
        contact.evaluate_with_load(
            side,
            &pose,
            &vel,
            positive("--load-kn", load)? * 1e3,
            1e-6,
            &mut ws,
        )?
    };
    pose.z = summary.z;
    print_patches(&contact, side, &pose, &summary, &ws.patches)?;
    if summary.load_iterations > 0 {
        let fz = summary.force_track[2] - summary.load_residual;
        if summary.load_residual.abs() > LOAD_RESIDUAL_NOTICE * fz {
            outln!("warning: {}", load_missed_text(fz, summary.load_residual));
        }
    }
    if let Some(out) = &a.out {
        write_single(out, side, &pose, &ws.patches)?;
        outln!("wrote {}", out.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// Why a prescribed load was not carried, for a warning.
fn load_missed_text(fz: f64, residual: f64) -> String {
    format!(
        "no height carries the load of {:.1} N: the vertical force jumps across it, and the \
         closest height gives {:.1} N ({:+.2} %); a zone appears or vanishes there, or a Hertz \
         patch in deep conformal flange contact changes its curvatures abruptly \
         (docs/models/contact.md §8)",
        fz,
        fz + residual,
        100.0 * residual / fz
    )
}

fn print_patches(
    contact: &WheelRailContact,
    side: Side,
    pose: &WheelsetPose,
    summary: &railsim_contact::WheelSummary,
    patches: &[PatchResult],
) -> Result<()> {
    outln!(
        "{} wheel, model {}, step {} mm: y = {:.3} mm, z = {:.4} mm, roll = {:.3} mrad, yaw = {:.3} mrad; {} patch(es), {} isosceles pairs",
        side.name(),
        contact.opts.model.name(),
        contact.opts.travel.step * 1e3,
        pose.y * 1e3,
        pose.z * 1e3,
        pose.roll * 1e3,
        pose.yaw * 1e3,
        patches.len(),
        summary.travel.pairs
    );
    if patches.is_empty() {
        outln!("no contact");
        return Ok(());
    }
    outln!(
        "{:>5} {:>11} {:>11} {:>9} {:>9} {:>10} {:>10} {:>10} {:>9} {:>9} {:>9} {:>10}",
        "patch",
        "y_rail[mm]",
        "y_wheel[mm]",
        "angle[°]",
        "pen[µm]",
        "Fn[N]",
        "Fx[N]",
        "Fs[N]",
        "Mz[N·m]",
        "2a[mm]",
        "2b[mm]",
        "pmax[MPa]"
    );
    for (i, p) in patches.iter().enumerate() {
        let f = &p.forces;
        outln!(
            "{:>5} {:>11.3} {:>11.3} {:>9.3} {:>9.3} {:>10.1} {:>10.1} {:>10.1} {:>9.3} {:>9.3} {:>9.3} {:>10.1}",
            i + 1,
            p.y_rail_profile * 1e3,
            p.y_wheel_profile * 1e3,
            p.contact_angle.to_degrees(),
            p.penetration * 1e6,
            f.fn_,
            f.fx,
            f.fs,
            f.mz,
            f.length * 1e3,
            f.width * 1e3,
            f.p_max * 1e-6
        );
    }
    outln!(
        "total force on the wheel, track frame: Fx = {:.1} N, Fy = {:.1} N, Fz = {:.1} N",
        summary.force_track[0],
        summary.force_track[1],
        summary.force_track[2]
    );
    Ok(())
}

const SINGLE_COLUMNS: [&str; 17] = [
    "side",
    "patch",
    "y_ws_mm",
    "z_ws_mm",
    "y_rail_mm",
    "y_wheel_mm",
    "contact_angle_rad",
    "penetration_mm",
    "fn_N",
    "fx_N",
    "fs_N",
    "mz_Nm",
    "length_mm",
    "width_mm",
    "pmax_MPa",
    "fy_track_N",
    "fz_track_N",
];

fn single_values(i: usize, pose: &WheelsetPose, p: &PatchResult) -> [f64; 16] {
    let f = &p.forces;
    [
        (i + 1) as f64,
        pose.y * 1e3,
        pose.z * 1e3,
        p.y_rail_profile * 1e3,
        p.y_wheel_profile * 1e3,
        p.contact_angle,
        p.penetration * 1e3,
        f.fn_,
        f.fx,
        f.fs,
        f.mz,
        f.length * 1e3,
        f.width * 1e3,
        f.p_max * 1e-6,
        p.force_track[1],
        p.force_track[2],
    ]
}

fn write_single(
    out: &Path,
    side: Side,
    pose: &WheelsetPose,
    patches: &[PatchResult],
) -> Result<()> {
    let ext = out
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let mut s = String::new();
    match ext.as_str() {
        "csv" => {
            s.push_str(&SINGLE_COLUMNS.join(","));
            s.push('\n');
            for (i, p) in patches.iter().enumerate() {
                let v = single_values(i, pose, p);
                s.push_str(side.name());
                for x in v {
                    write!(s, ",{x}").unwrap();
                }
                s.push('\n');
            }
        }
        "json" => {
            let arr: Vec<serde_json::Value> = patches
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let v = single_values(i, pose, p);
                    let mut m = serde_json::Map::new();
                    m.insert("side".into(), side.name().into());
                    for (k, x) in SINGLE_COLUMNS[1..].iter().zip(v) {
                        m.insert((*k).into(), x.into());
                    }
                    serde_json::Value::Object(m)
                })
                .collect();
            s = serde_json::to_string_pretty(&arr)?;
            s.push('\n');
        }
        _ => bail!(
            "--out {}: expected a file name ending in .csv or .json, found extension \"{ext}\"",
            out.display()
        ),
    }
    std::fs::write(out, s).with_context(|| format!("writing {}", out.display()))
}

/// Batch output columns: CONTACT's names and conventions.
const BATCH_COLUMNS: [&str; 18] = [
    "case",
    "side",
    "icp",
    "z_ws_mm",
    "ycp_r_mm",
    "delttr_rad",
    "pen_mm",
    "fn_N",
    "fx_N",
    "fs_N",
    "mz_Nmm",
    "pmax_N_mm2",
    "length_x_mm",
    "width_s_mm",
    "cksi",
    "ceta",
    "cphi_rad_mm",
    "ycp_w_mm",
];

fn run_batch(
    contact: &WheelRailContact,
    cases: &Path,
    out: &Path,
    ws: &mut ContactWorkspace,
) -> Result<ExitCode> {
    let text =
        std::fs::read_to_string(cases).with_context(|| format!("reading {}", cases.display()))?;
    let name = cases.display().to_string();
    let list = parse_cases_csv(&text, &name)?;
    // the single-case --spin-rad-s's range: a wheelset spinning more than ten times as fast as
    // it rolls is a unit or sign error (creepages of thousands)
    let r0 = contact.pair.r0;
    for (label, case) in &list {
        let limit = 10.0 * case.speed_mm_s * 1e-3 / r0;
        if case.vpitch_rad_s.abs() > limit {
            bail!(
                "{name}: case {label}: vpitch_rad_s = {} is implausible, expected within ±{} rad/s (ten times the rolling rate speed / r0 = {} mm/s / {} mm)",
                railsim_profile::short_number(case.vpitch_rad_s),
                railsim_profile::short_number(limit),
                case.speed_mm_s,
                r0 * 1e3
            );
        }
    }
    let mut s = BATCH_COLUMNS.join(",");
    s.push('\n');
    let mut rows: Vec<ContactRow> = Vec::new();
    let (mut n_rows, mut missed) = (0, 0);
    for (label, case) in &list {
        let solved = solve_case(contact, case, ws, &mut rows).with_context(|| {
            format!(
                "{name}: case {label} ({} wheel, y_ws = {} mm; the quantities named below are in railsim's conventions, SI, y to the left and z up, which mirror CONTACT's y and yaw: docs/conventions.md)",
                case.side.name(),
                case.y_ws_mm
            )
        })?;
        let z = solved.z_mm;
        if let Some(fz) = case.fz_target_n
            && solved.load_residual_n.abs() > LOAD_RESIDUAL_NOTICE * fz
        {
            missed += 1;
            eprintln!(
                "warning: {name}: case {label} ({} wheel, y_ws = {} mm): {}",
                case.side.name(),
                case.y_ws_mm,
                load_missed_text(fz, solved.load_residual_n)
            );
        }
        for (i, r) in rows.iter().enumerate() {
            write!(
                s,
                "{label},{},{},{z},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                case.side.name(),
                i + 1,
                r.ycp_r_mm,
                r.delttr_rad,
                r.pen_mm,
                r.fn_n,
                r.fx_n,
                r.fs_n,
                r.mz_nmm,
                r.pmax_n_mm2,
                r.length_x_mm,
                r.width_s_mm,
                r.cksi,
                r.ceta,
                r.cphi_rad_mm,
                r.ycp_w_mm
            )
            .unwrap();
            s.push('\n');
            n_rows += 1;
        }
    }
    std::fs::write(out, s).with_context(|| format!("writing {}", out.display()))?;
    outln!(
        "{} cases, {} patch rows written to {}{}",
        list.len(),
        n_rows,
        out.display(),
        if missed > 0 {
            format!("; {missed} case(s) do not carry their load (warnings above)")
        } else {
            String::new()
        }
    );
    Ok(ExitCode::SUCCESS)
}

fn run_conicity(a: &ConicityArgs) -> Result<ExitCode> {
    let (wheel, rail) = profiles(&a.pair)?;
    let setup = WheelsetTrackSetup {
        gauge: gauge_mm(&a.pair)? * 1e-3,
        gauge_depth: 0.014,
        inclination_rad: parse_inclination(&a.pair.inclination)?,
        flange_back_spacing: flange_back_mm(&a.pair)? * 1e-3,
        flange_back_y: flange_back_y_mm(&a.pair)? * 1e-3,
        r0: r0_mm(&a.pair)? * 1e-3,
    };
    // Checked before anything is printed: the friction (for Nadal's limit) and the
    // amplitudes (Δr(y) is sampled over ±10 mm, so amplitudes up to 9.9 mm).
    let friction = friction(&a.pair)?;
    friction.check()?;
    let mut amplitudes = Vec::with_capacity(a.amplitudes_mm.len());
    for &amp in &a.amplitudes_mm {
        let amp_m = positive("--amplitudes-mm", amp)? * 1e-3;
        if amp_m > 0.0099 {
            bail!(
                "--amplitudes-mm: expected amplitudes up to 9.9 mm, found {}",
                railsim_profile::short_number(amp)
            );
        }
        amplitudes.push((amp, amp_m));
    }
    let ys: Vec<f64> = (-400..=400).map(|i| i as f64 * 25e-6).collect();
    // (the contact-point jumps located, so that λe does not depend on the grid near them)
    let samples = rolling_radius_difference_with_jumps(&wheel, &rail, &setup, &ys, 1e-3)?;
    outln!(
        "{:>8} {:>10} {:>12} {:>12} {:>10} {:>10}",
        "y[mm]",
        "Δr[mm]",
        "S_left[mm]",
        "S_right[mm]",
        "γL[°]",
        "γR[°]"
    );
    for s in samples
        .iter()
        .filter(|s| ((s.y_ws * 1e3 * 2.0).round() - s.y_ws * 2e3).abs() < 1e-9 && s.y_ws >= 0.0)
    {
        outln!(
            "{:>8.2} {:>10.4} {:>12.3} {:>12.3} {:>10.3} {:>10.3}",
            s.y_ws * 1e3,
            s.delta_r * 1e3,
            s.y_contact_wheel_left * 1e3,
            s.y_contact_wheel_right * 1e3,
            s.contact_angle_left.to_degrees(),
            s.contact_angle_right.to_degrees()
        );
    }
    let e0 = 0.5 * (setup.flange_back_spacing - 2.0 * setup.flange_back_y);
    outln!(
        "{:>14} {:>12} {:>12} {:>14}",
        "amplitude[mm]",
        "λe harmonic",
        "λe kinematic",
        "wavelength[m]"
    );
    for &(amp, amp_m) in &amplitudes {
        let f = |y: f64| delta_r_interp(&samples, y);
        let h = equivalent_conicity_harmonic(f, amp_m);
        let k = equivalent_conicity_kinematic(f, amp_m, e0, setup.r0);
        match k {
            Some((lk, l)) => outln!("{amp:>14.2} {h:>12.4} {lk:>12.4} {l:>14.2}"),
            None => outln!("{amp:>14.2} {h:>12.4} {:>12} {:>14}", "-", "-"),
        }
    }
    // the flange's climbing limit, with the friction at the flank's angle
    match flange_angle(&wheel)? {
        Some(f) => {
            let mu = friction.at(f.angle);
            outln!(
                "flange angle {:.2}° at S = {:.2} mm (the wheel profile's steepest flank, against its \
             axle); Nadal's limit of Y/Q at μ = {mu}: {:.3}",
                f.angle.to_degrees(),
                f.y * 1e3,
                nadal_limit(f.angle, mu)
            );
        }
        None => outln!(
            "no flange angle: the wheel profile has no flank of {:.0}° to 90° between its lowest \
             point left of the taping line (y = 0) and the taping line",
            MIN_FLANGE_ANGLE.to_degrees()
        ),
    }
    // the flange's inspection dimensions (Sh, Sd, qR; contact-theory note §5.1)
    match flange_dimensions(&wheel, setup.flange_back_y)? {
        Some(d) => outln!(
            "flange dimensions: Sh {:.2} mm (tip at S = {:.2} mm), Sd {:.2} mm (10 mm from the \
             taping line, from the flange back at S = {:.2} mm), qR {:.2} mm",
            d.height * 1e3,
            d.tip[0] * 1e3,
            d.thickness * 1e3,
            setup.flange_back_y * 1e3,
            d.qr * 1e3
        ),
        None => outln!(
            "no flange dimensions: the wheel profile reaches no flange tip over 12 mm high \
             between its ends left of the taping line (y = 0), or does not reach y = 0"
        ),
    }
    Ok(ExitCode::SUCCESS)
}

//! Conversion to and from the conventions of Vollebregt's CONTACT (module 1, wheel/rail), so
//! that railsim's batch results compare column by column with CONTACT's reference files.
//!
//! CONTACT's track frame has x along the track, y to the **right** and z **down**; railsim's has
//! y to the left and z up. The two differ by a rotation of pi about x, so roll keeps its sign
//! while yaw and pitch change sign. CONTACT reports forces **on the rail**, creepages of the
//! rail relative to the wheel, lengths in mm, and profile coordinates whose lateral axis points
//! along CONTACT's track y for both rails (checked against the benchmark output: the left rail's
//! `ycp_r` grows toward the track centre). See `docs/conventions.md`.

use crate::model::PatchResult;
use crate::pose::{Side, WheelsetPose, WheelsetVelocity};

/// One wheel/rail case in CONTACT's input conventions (mm, rad, rad/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactCase {
    /// Which wheel.
    pub side: Side,
    /// \[mm\] lateral wheelset position, CONTACT y (to the right)
    pub y_ws_mm: f64,
    /// \[rad\] yaw, CONTACT convention
    pub yaw_ws_rad: f64,
    /// \[rad\] roll, CONTACT convention (same as railsim's)
    pub roll_ws_rad: f64,
    /// \[rad/s\] pitch velocity about CONTACT's y-axis (negative when rolling forward)
    pub vpitch_rad_s: f64,
    /// \[mm\] vertical wheelset position (down), if prescribed
    pub z_ws_mm: Option<f64>,
    /// \[N\] vertical force on the rail, if prescribed
    pub fz_target_n: Option<f64>,
    /// \[mm/s\] forward speed
    pub speed_mm_s: f64,
}

impl ContactCase {
    /// The railsim pose and velocity of this case (SI, railsim frame).
    pub fn to_railsim(&self) -> (WheelsetPose, WheelsetVelocity) {
        let pose = WheelsetPose {
            y: -self.y_ws_mm * 1e-3,
            z: -self.z_ws_mm.unwrap_or(0.0) * 1e-3,
            roll: self.roll_ws_rad,
            yaw: -self.yaw_ws_rad,
        };
        let vel = WheelsetVelocity {
            vx: self.speed_mm_s * 1e-3,
            spin: -self.vpitch_rad_s,
            ..Default::default()
        };
        (pose, vel)
    }
}

/// One patch in CONTACT's output conventions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactRow {
    /// \[mm\] lateral contact position in rail-profile coordinates (CONTACT orientation)
    pub ycp_r_mm: f64,
    /// \[rad\] contact angle about the track x-axis (CONTACT sign: positive on the left rail
    /// toward the flange, negative on the right)
    pub delttr_rad: f64,
    /// \[mm\] penetration
    pub pen_mm: f64,
    /// \[N\] normal force on the rail
    pub fn_n: f64,
    /// \[N\] longitudinal force on the rail
    pub fx_n: f64,
    /// \[N\] lateral force on the rail along CONTACT's inclined s-axis
    pub fs_n: f64,
    /// \[N mm\] spin moment on the rail about CONTACT's normal
    pub mz_nmm: f64,
    /// \[N/mm^2\] maximum pressure
    pub pmax_n_mm2: f64,
    /// \[mm\] patch length along x
    pub length_x_mm: f64,
    /// \[mm\] patch width along s
    pub width_s_mm: f64,
    /// \[-\] longitudinal creepage of the rail relative to the wheel (on CONTACT's reference
    /// speed, the mean of the forward and the circumferential speed, as the next two)
    pub cksi: f64,
    /// \[-\] lateral creepage of the rail relative to the wheel
    pub ceta: f64,
    /// \[rad/mm\] spin creepage of the rail relative to the wheel
    pub cphi_rad_mm: f64,
    /// \[mm\] wheel-profile lateral coordinate of the contact (CONTACT orientation)
    pub ycp_w_mm: f64,
}

/// Express a railsim patch in CONTACT's conventions.
pub fn to_contact(side: Side, p: &PatchResult) -> ContactRow {
    // CONTACT's lateral profile axes follow its track y (to the right): field-positive on the
    // right rail, gauge-positive on the left.
    let lat = match side {
        Side::Right => 1.0,
        Side::Left => -1.0,
    };
    let sg = side.sign();
    let f = &p.forces;
    // The side-frame patch axes: s toward the field, n up. CONTACT's s-axis is its track y
    // rotated by delttr; its normal points into the rail. Force on the rail = -force on wheel.
    // Left side: CONTACT s = -(side s), n_c = -(side n)  =>  fs_c = +fs, fn_c = +fn.
    // Right side: CONTACT s = +(side s), n_c = -(side n) =>  fs_c = -fs, fn_c = +fn.
    let fs_c = -lat * f.fs;
    // Spin moment on the rail about n_c = -n: (-mz) * (-1) = mz on both sides in the side
    // frame; the mirror of the right side flips the sense of rotation.
    let mz_c = sg * f.mz;
    // Creepages of the rail relative to the wheel, CONTACT axes, and on CONTACT's reference
    // speed: it divides the slip by the rolling velocity, the mean of the forward and the
    // circumferential speed (Kalker 1990; CONTACT's `wr_creep_cref`; the reference files'
    // `veloc_mm_s` = V (1 + cksi/2) in every row), railsim by the forward speed V. The ratio
    // V / veloc = 1 / (1 + ξ_c/2), ξ_c railsim's longitudinal creepage in CONTACT's sign
    // (second-order in it: 1.3 % in ceta and cphi on the benchmark's flange cases).
    let c = &p.creepages;
    let scale = 1.0 / (1.0 - 0.5 * c.xi);
    ContactRow {
        ycp_r_mm: lat * p.y_rail_profile * 1e3,
        delttr_rad: sg * p.contact_angle,
        pen_mm: p.penetration * 1e3,
        fn_n: f.fn_,
        fx_n: -f.fx,
        fs_n: fs_c,
        mz_nmm: mz_c * 1e3,
        pmax_n_mm2: f.p_max * 1e-6,
        length_x_mm: f.length * 1e3,
        width_s_mm: f.width * 1e3,
        cksi: -c.xi * scale,
        ceta: -lat * c.eta * scale,
        cphi_rad_mm: sg * c.phi * 1e-3 * scale,
        ycp_w_mm: lat * p.y_wheel_profile * 1e3,
    }
}

/// Error in a table of cases: the first bad line, and the problems of further bad lines (one
/// per line, at most [`MAX_CASE_ERRORS`] in all) so that a table is mended in one pass.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseError {
    /// File name or other source label.
    pub source_name: String,
    /// 1-based line number.
    pub line: usize,
    /// What is wrong, naming the column and the value.
    pub message: String,
    /// Further bad lines: (1-based line, what is wrong).
    pub more: Vec<(usize, String)>,
    /// Bad lines beyond those reported.
    pub unreported: usize,
}

/// Most bad lines of a case table reported in one [`CaseError`].
pub const MAX_CASE_ERRORS: usize = 20;

impl std::fmt::Display for CaseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: {}", self.source_name, self.line, self.message)?;
        for (line, message) in &self.more {
            write!(f, "\n{}:{line}: {message}", self.source_name)?;
        }
        if self.unreported > 0 {
            write!(
                f,
                "\n{}: {} more bad lines not shown",
                self.source_name, self.unreported
            )?;
        }
        Ok(())
    }
}

impl std::error::Error for CaseError {}

/// Read a comma-separated table of cases with CONTACT's column names: `side`, `y_ws_mm`,
/// `yaw_ws_rad`, `roll_ws_rad`, `vpitch_rad_s`, and `fz_target_N` or `z_ws_mm` (an empty
/// `fz_target_N` means the position is prescribed). Optional `case` (a label), and `speed_mm_s`
/// (default 2000). Other columns are ignored, so CONTACT's reference files can be read as they
/// are. Returns the cases with their labels.
pub fn parse_cases_csv(
    text: &str,
    source_name: &str,
) -> Result<Vec<(String, ContactCase)>, CaseError> {
    let err = |line: usize, message: String| CaseError {
        source_name: source_name.to_string(),
        line,
        message,
        more: vec![],
        unreported: 0,
    };
    // (a byte-order mark, as spreadsheet programs write, is not part of the first column's name)
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (hline, header) = lines
        .next()
        .ok_or_else(|| err(1, "the file is empty: expected a header line".into()))?;
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    if let Some((k, dup)) = cols
        .iter()
        .enumerate()
        .find(|(k, c)| !c.is_empty() && cols[..*k].iter().any(|p| p.eq_ignore_ascii_case(c)))
    {
        return Err(err(
            hline,
            format!(
                "column '{dup}' appears twice (again as column {}): expected each column once",
                k + 1
            ),
        ));
    }
    let find = |name: &str| cols.iter().position(|c| c.eq_ignore_ascii_case(name));
    let need = |name: &'static str| {
        find(name).ok_or_else(|| {
            err(
                hline,
                format!("missing column '{name}': expected side, y_ws_mm, yaw_ws_rad, roll_ws_rad, vpitch_rad_s and fz_target_N or z_ws_mm"),
            )
        })
    };
    let c_side = need("side")?;
    let c_y = need("y_ws_mm")?;
    let c_yaw = need("yaw_ws_rad")?;
    let c_roll = need("roll_ws_rad")?;
    let c_vp = need("vpitch_rad_s")?;
    let c_fz = find("fz_target_N");
    let c_z = find("z_ws_mm");
    if c_fz.is_none() && c_z.is_none() {
        return Err(err(
            hline,
            "missing column: expected fz_target_N or z_ws_mm".into(),
        ));
    }
    let c_case = find("case");
    let c_v = find("speed_mm_s");
    let mut out = Vec::new();
    let mut bad: Option<CaseError> = None;
    for (ln, l) in lines {
        // (a bad line is reported and the next one read: every bad line in one pass)
        let row = (|| -> Result<(ContactCase, Option<String>), CaseError> {
            let f: Vec<&str> = l.split(',').map(str::trim).collect();
            let get = |c: usize, name: &str| -> Result<&str, CaseError> {
                f.get(c).copied().ok_or_else(|| {
                    err(
                        ln,
                        format!(
                            "column '{name}' is missing: the line has only {} fields",
                            f.len()
                        ),
                    )
                })
            };
            let num = |c: usize, name: &str| -> Result<f64, CaseError> {
                let s = get(c, name)?;
                let v: f64 = s.parse().map_err(|_| {
                    err(
                        ln,
                        format!("column '{name}': expected a number, found \"{s}\""),
                    )
                })?;
                if !v.is_finite() {
                    return Err(err(
                        ln,
                        format!("column '{name}': expected a finite number, found \"{s}\""),
                    ));
                }
                Ok(v)
            };
            let opt_num = |c: Option<usize>, name: &str| -> Result<Option<f64>, CaseError> {
                match c {
                    Some(c) if f.get(c).is_some_and(|s| !s.is_empty()) => num(c, name).map(Some),
                    _ => Ok(None),
                }
            };
            let side = match get(c_side, "side")?.to_ascii_lowercase().as_str() {
                "left" | "l" => Side::Left,
                "right" | "r" => Side::Right,
                other => {
                    return Err(err(
                        ln,
                        format!("column 'side': expected left or right, found \"{other}\""),
                    ));
                }
            };
            let fz = opt_num(c_fz, "fz_target_N")?;
            let z = opt_num(c_z, "z_ws_mm")?;
            if fz.is_none() && z.is_none() {
                return Err(err(
                    ln,
                    "expected a value in fz_target_N or z_ws_mm, found neither".into(),
                ));
            }
            let case = ContactCase {
                side,
                y_ws_mm: num(c_y, "y_ws_mm")?,
                yaw_ws_rad: num(c_yaw, "yaw_ws_rad")?,
                roll_ws_rad: num(c_roll, "roll_ws_rad")?,
                vpitch_rad_s: num(c_vp, "vpitch_rad_s")?,
                z_ws_mm: if fz.is_some() { None } else { z },
                fz_target_n: fz,
                speed_mm_s: opt_num(c_v, "speed_mm_s")?.unwrap_or(2000.0),
            };
            let label = c_case.map(|c| f.get(c).map(|s| s.to_string()).unwrap_or_default());
            Ok((case, label))
        })();
        match (row, &mut bad) {
            (Ok((case, label)), None) => {
                out.push((label.unwrap_or_else(|| format!("{}", out.len() + 1)), case));
            }
            (Ok(_), Some(_)) => {}
            (Err(e), None) => bad = Some(e),
            (Err(e), Some(first)) => {
                if first.more.len() + 1 < MAX_CASE_ERRORS {
                    first.more.push((e.line, e.message));
                } else {
                    first.unreported += 1;
                }
            }
        }
    }
    match bad {
        Some(e) => Err(e),
        None => Ok(out),
    }
}

/// What [`solve_case`] found besides the patches.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolvedCase {
    /// \[mm\] the vertical wheelset position (CONTACT's z, down).
    pub z_mm: f64,
    /// \[N\] the vertical force minus the prescribed load (0 without one;
    /// `WheelSummary::load_residual`).
    pub load_residual_n: f64,
}

/// Solve one case: with the load prescribed, the wheelset height is iterated; otherwise the
/// position is used as given. Fills `rows` with the patches in CONTACT's conventions.
pub fn solve_case(
    contact: &crate::model::WheelRailContact,
    case: &ContactCase,
    ws: &mut crate::model::ContactWorkspace,
    rows: &mut Vec<ContactRow>,
) -> Result<SolvedCase, crate::error::ContactError> {
    let (pose, vel) = case.to_railsim();
    let summary = match case.fz_target_n {
        Some(fz) => contact.evaluate_with_load(case.side, &pose, &vel, fz, 1e-6, ws)?,
        None => contact.evaluate(case.side, &pose, &vel, ws)?,
    };
    rows.clear();
    rows.extend(ws.patches.iter().map(|p| to_contact(case.side, p)));
    Ok(SolvedCase {
        z_mm: -summary.z * 1e3,
        load_residual_n: summary.load_residual,
    })
}

/// The wheel/rail pair of CONTACT's Manchester benchmark inputs (`mbench_a22_*.inp`): the given
/// profiles (the benchmark's `.prw`/`.prr`, whose rail is already inclined 1:40), gauge 1435 mm
/// measured 14 mm below the rail top, no further inclination, flange-back distance 1360 mm with
/// the flange back at profile y = -70 mm, r0 = 460 mm, G = 82 GPa, nu = 0.28, mu = 0.3.
pub fn manchester_benchmark_spec(
    wheel: railsim_profile::Profile,
    rail: railsim_profile::Profile,
) -> crate::pair::PairSpec {
    crate::pair::PairSpec {
        wheel,
        rail,
        r0: 0.460,
        flange_back_distance: 1.360,
        flange_back_y: -0.070,
        gauge: 1.435,
        gauge_depth: 0.014,
        inclination: 0.0,
        material: railsim_elastic::Material { g: 82e9, nu: 0.28 },
        friction: crate::Friction::Constant(0.3),
        curve_ds: 5e-5,
        smoothing: 0.0,
    }
}

/// The Manchester benchmark pair built from the profile files shipped in the repository
/// (`vehicles/profiles/MBench_S1002_v3.prw`, `tracks/profiles/MBench_UIC60_v3.prr`) below
/// `repo_root`, with [`manchester_benchmark_spec`].
pub fn manchester_benchmark_pair(
    repo_root: &std::path::Path,
) -> Result<crate::pair::WheelRailPair, crate::error::ContactError> {
    use railsim_profile::{ProfileKind, read_simpack};
    let wheel = read_simpack(
        &repo_root.join("vehicles/profiles/MBench_S1002_v3.prw"),
        ProfileKind::Wheel,
    )?;
    let rail = read_simpack(
        &repo_root.join("tracks/profiles/MBench_UIC60_v3.prr"),
        ProfileKind::Rail,
    )?;
    crate::pair::WheelRailPair::new(&manchester_benchmark_spec(wheel, rail))
}

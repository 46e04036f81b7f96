//! `railsim statics [VEHICLE]`: a vehicle's static equilibrium on level track (the wheel loads,
//! and with `--elements` every force element's static force) and, with `--twist-permille`, its
//! wheels' unloading on a uniformly twisted track, or with `--bogie-twist-permille` on a track
//! twisted over the bogie-centre distance and over each bogie's wheelbase by different amounts
//! (`VehicleModel::static_equilibrium_on`, docs/models/vehicle.md "Statics").

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Result, bail};
use clap::Args;

use railsim_vehicle::{BOGIE_FRAME_MIN_OFFSET, Bogie, DofKind, VehicleModel};

/// The built-in vehicle, from the repository this binary was built in.
pub const DEFAULT_VEHICLE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../vehicles/manchester_vehicle1.toml"
);

/// \[‰\] the largest twist `--twist-permille` and `--bogie-twist-permille` take.
const MAX_TWIST_PERMILLE: f64 = 50.0;

#[derive(Args)]
pub struct StaticsArgs {
    /// Vehicle file; default: the built-in vehicles/manchester_vehicle1.toml.
    pub vehicle: Option<PathBuf>,
    /// Track twist g (‰: mm of cross-level per metre along the track): the cross-level
    /// c(x) = g (x − x̄) about the middle x̄ of the end wheelsets, the left rail c/2 up and the
    /// right c/2 down under the wheels' running circles; positive: the left rail rises toward
    /// the front (+x). Reports each wheel's unloading ΔQ/Q0 against --limit. Alone, one twist
    /// over the whole vehicle; with --bogie-twist-permille, the twist G* over the bogie-centre
    /// distance (the carbody twist) only, see there.
    #[arg(long)]
    pub twist_permille: Option<f64>,
    /// Twist G+ (‰) over each bogie's wheelbase, superposed on the twist G* over the
    /// bogie-centre distance given by --twist-permille (0 without it), as EN 14363 twists a
    /// bogie's wheelbase and the bogie-centre distance by different amounts: a wheelset at x in
    /// the bogie whose frame is at x_b gets the cross-level c = G* (x_b − x̄_b) + G+ (x − x_b),
    /// x̄_b the middle of the outermost bogie frames. Each bogie's centre thus sits on the
    /// carbody twist and its wheelbase is twisted by G+ in all (not G* + G+) about its centre.
    /// Bogies as in the run's assessment: the carbody is the heaviest rigid body, the bogie
    /// frames the other rigid bodies at least 0.5 m in x from its centre, each wheelset in the
    /// bogie whose frame is nearest in x. Both values come from the user (from the edition of
    /// EN 14363 that applies; none is built in).
    #[arg(long)]
    pub bogie_twist_permille: Option<f64>,
    /// Limit of the wheel unloading ΔQ/Q0 on the twisted track (EN 14363's commonly quoted 0.6;
    /// check it against the edition that applies).
    #[arg(long, default_value_t = 0.6)]
    pub limit: f64,
    /// List every force element's static force and moment (on its body 2, local axes).
    #[arg(long)]
    pub elements: bool,
}

/// `railsim statics`.
pub fn run_statics(a: &StaticsArgs) -> Result<ExitCode> {
    for (option, value) in [
        ("--twist-permille", a.twist_permille),
        ("--bogie-twist-permille", a.bogie_twist_permille),
    ] {
        if let Some(g) = value
            && !(g.is_finite() && g.abs() <= MAX_TWIST_PERMILLE)
        {
            bail!(
                "{option}: expected a number from -{MAX_TWIST_PERMILLE} to {MAX_TWIST_PERMILLE}, found {g}"
            );
        }
    }
    if !(a.limit > 0.0 && a.limit <= 1.0) {
        bail!(
            "--limit: expected a wheel unloading ΔQ/Q0 in (0, 1], found {}",
            a.limit
        );
    }
    let path = a
        .vehicle
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_VEHICLE));
    let v = VehicleModel::from_file(&path)?;
    let level = v.static_equilibrium()?;
    let mass = v.total_mass();
    let weight = mass * v.gravity();
    outln!(
        "railsim statics: {} ({} bodies, {} wheelsets, {:.0} kg, weight {:.2} kN); linear statics on level track",
        v.name(),
        v.bodies().len(),
        v.wheelsets().len(),
        mass,
        weight * 1e-3
    );
    let order = v.wheelsets_from_front();
    outln!("static wheel loads Q0 (kN):");
    for &i in &order {
        let w = &v.wheelsets()[i];
        let q = level.wheel_loads[i];
        outln!(
            "  {:<12} x = {:7.3} m: left {:8.3}, right {:8.3}",
            w.name,
            w.position[0],
            q[0] * 1e-3,
            q[1] * 1e-3
        );
    }
    let total = level.total_wheel_load();
    outln!(
        "  sum {:.3} kN against the weight {:.3} kN{}",
        total * 1e-3,
        weight * 1e-3,
        if (total - weight).abs() > 1e-6 * weight {
            " (frozen degrees of freedom or elements to the track carry the rest)"
        } else {
            ""
        }
    );
    if a.elements {
        outln!("static forces of the elements on their body 2, local axes (N; N·m):");
        for (f, e) in v.forces().iter().zip(&level.element_force) {
            // (rounded to the printed 0.1, then + 0.0: no "-0.0" for a force that rounds to 0)
            let e = e.map(|x| (x * 10.0).round() / 10.0 + 0.0);
            outln!(
                "  {:<28} F [{:10.1} {:10.1} {:10.1}]  M [{:9.1} {:9.1} {:9.1}]",
                f.name,
                e[0],
                e[1],
                e[2],
                e[3],
                e[4],
                e[5]
            );
        }
    }
    if a.twist_permille.is_none() && a.bogie_twist_permille.is_none() {
        return Ok(ExitCode::SUCCESS);
    }
    // the option that asked for the twist, for the errors
    let option = if a.bogie_twist_permille.is_some() {
        "--bogie-twist-permille"
    } else {
        "--twist-permille"
    };
    // a wheelset held vertically cannot follow its rails: its support would just press it
    if let Some(w) = v
        .wheelsets()
        .iter()
        .find(|w| w.frozen[DofKind::Z.index()] || w.frozen[DofKind::Roll.index()])
    {
        bail!(
            "{option}: wheelset '{}' of vehicle '{}' has its z or roll frozen, so it cannot follow a twisted track",
            w.name,
            v.name()
        );
    }
    // \[m\] each wheelset's cross-level, left rail up; and the lines that describe the twist
    let g_body = a.twist_permille.unwrap_or(0.0);
    let (cross, header) = match a.bogie_twist_permille {
        None => uniform_twist(&v, g_body)?,
        Some(g_bogie) => combined_twist(&v, g_body, g_bogie)?,
    };
    let heights: Vec<[f64; 2]> = cross.iter().map(|&c| [0.5 * c, -0.5 * c]).collect();
    let twisted = v.static_equilibrium_on(&heights)?;
    for line in header {
        outln!("{line}");
    }
    let mut worst: Option<(f64, usize, usize)> = None;
    for &i in &order {
        let w = &v.wheelsets()[i];
        let (q0, q) = (level.wheel_loads[i], twisted.wheel_loads[i]);
        // (none for a wheel without static load, e.g. a wheelset held by frozen freedoms)
        let unload = |k: usize| (q0[k] > 0.0).then(|| (q0[k] - q[k]) / q0[k]);
        let text = |k: usize| unload(k).map_or("-".to_owned(), |u| format!("{u:+.3}"));
        for k in 0..2 {
            if let Some(u) = unload(k)
                && worst.is_none_or(|(w, _, _)| u > w)
            {
                worst = Some((u, i, k));
            }
        }
        outln!(
            "  {:<12} left Q {:8.3} kN (ΔQ/Q0 {}), right Q {:8.3} kN (ΔQ/Q0 {})",
            w.name,
            q[0] * 1e-3,
            text(0),
            q[1] * 1e-3,
            text(1)
        );
    }
    if let Some((u, i, k)) = worst {
        let verdict = if u > 1.0 {
            "LIFTED: beyond the linear statics, which lets a wheel pull on its rail"
        } else if u > a.limit {
            "EXCEEDED"
        } else {
            "within"
        };
        outln!(
            "largest unloading ΔQ/Q0 = {u:.3} ({} {} wheel), limit {}: {verdict}",
            v.wheelsets()[i].name,
            ["left", "right"][k],
            a.limit
        );
    }
    outln!(
        "note: linear statics: every element with its stiffness at zero deflection (a bump stop in its clearance carries nothing, friction and series dampers nothing); for nonlinear characteristics run the vehicle slowly over a twist ramp (`railsim run`: the summary's least Q and ΔQ/Q0 per wheel)"
    );
    Ok(ExitCode::SUCCESS)
}

/// \[m\] each wheelset's cross-level (left rail up) on the track twisted uniformly by `g`
/// \[‰\], c = g (x − x̄) about the middle x̄ of the end wheelsets, and the line that describes
/// it. Fails when `v` has no two wheelsets at different x.
fn uniform_twist(v: &VehicleModel, g: f64) -> Result<(Vec<f64>, Vec<String>)> {
    let xs: Vec<f64> = v.wheelsets().iter().map(|w| w.position[0]).collect();
    let (lo, hi) = x_range(xs.iter().copied());
    if hi <= lo {
        bail!(
            "--twist-permille: vehicle '{}' has no two wheelsets at different x: a uniform twist needs a wheelbase",
            v.name()
        );
    }
    let mid = 0.5 * (lo + hi);
    let cross = |x: f64| g * 1e-3 * (x - mid);
    let header = format!(
        "on a twist of {g} ‰ (cross-level {:+.2} mm at the front wheelset, {:+.2} mm at the rear):",
        cross(hi) * 1e3,
        cross(lo) * 1e3
    );
    Ok((xs.into_iter().map(cross).collect(), vec![header]))
}

/// The bogies of `v` ([`VehicleModel::bogies`], the rule of the run's assessment); fails,
/// naming `--bogie-twist-permille` and what was found, when it has none.
fn find_bogies(v: &VehicleModel) -> Result<Vec<Bogie>> {
    let bogies = v.bogies();
    if !bogies.is_empty() {
        return Ok(bogies);
    }
    let bodies = v.bodies();
    let Some(cb) = v.carbody() else {
        bail!(
            "--bogie-twist-permille: vehicle '{}' has no bogie frame: expected a carbody (the heaviest rigid body) and bogie frames (other rigid bodies at least {BOGIE_FRAME_MIN_OFFSET} m in x from its centre, as in the run's assessment), found no rigid body",
            v.name()
        );
    };
    let carbody = &bodies[cb.index()];
    let others: Vec<String> = (0..bodies.len())
        .filter(|&i| i != cb.index())
        .map(|i| named_at(&bodies[i].name, bodies[i].position[0]))
        .collect();
    bail!(
        "--bogie-twist-permille: vehicle '{}' has no bogie frame: expected, besides the carbody '{}' (the heaviest rigid body, x = {:.3} m), rigid bodies at least {BOGIE_FRAME_MIN_OFFSET} m in x from its centre with wheelsets nearest to them (as in the run's assessment), found {}",
        v.name(),
        carbody.name,
        carbody.position[0],
        if others.is_empty() {
            "no other rigid body".to_owned()
        } else {
            format!(
                "{} with {} wheelset(s)",
                others.join(", "),
                v.wheelsets().len()
            )
        }
    );
}

/// \[m\] each wheelset's cross-level (left rail up) on the track twisted by `g_body` \[‰\] over
/// the bogie-centre distance and `g_bogie` \[‰\] over each bogie's wheelbase:
/// c = G* (x_b − x̄_b) + G+ (x − x_b) for a wheelset at x in the bogie whose frame is at x_b, x̄_b
/// the middle of the outermost frames; and the lines that describe it (the header, then each
/// bogie's and wheelset's cross-level, from the front). Fails when `v` has no
/// bogies, `g_bogie` is not 0 and a bogie has no two wheelsets at different x, or `g_body` is
/// not 0 and the bogie frames all sit at one x.
fn combined_twist(v: &VehicleModel, g_body: f64, g_bogie: f64) -> Result<(Vec<f64>, Vec<String>)> {
    let bogies = find_bogies(v)?;
    let bodies = v.bodies();
    let ws = v.wheelsets();
    // (a bogie without a wheelbase cannot be twisted over it; with G+ = 0 none is asked for)
    for g in bogies.iter().filter(|_| g_bogie != 0.0) {
        let (lo, hi) = x_range(g.wheelsets.iter().map(|i| ws[i.index()].position[0]));
        if hi <= lo {
            let names: Vec<String> = g
                .wheelsets
                .iter()
                .map(|i| named_at(&ws[i.index()].name, ws[i.index()].position[0]))
                .collect();
            bail!(
                "--bogie-twist-permille: bogie frame '{}' of vehicle '{}' has {} wheelset(s) ({}): a twist over its wheelbase needs two at different x",
                bodies[g.frame.index()].name,
                v.name(),
                g.wheelsets.len(),
                names.join(", ")
            );
        }
    }
    let frame_x = |g: &Bogie| bodies[g.frame.index()].position[0];
    let (lo, hi) = x_range(bogies.iter().map(frame_x));
    if g_body != 0.0 && hi <= lo {
        let names: Vec<String> = bogies
            .iter()
            .map(|g| named_at(&bodies[g.frame.index()].name, frame_x(g)))
            .collect();
        bail!(
            "--twist-permille with --bogie-twist-permille: vehicle '{}' has {} bogie frame(s) ({}), none at another x: a twist over the bogie-centre distance needs two bogies at different x",
            v.name(),
            bogies.len(),
            names.join(", ")
        );
    }
    let mid = 0.5 * (lo + hi);
    // [mm] rounded to the printed µm, then + 0.0: no "-0.000" for a cross-level that rounds to 0
    let mm = |c: f64| (c * 1e6).round() / 1e3 + 0.0;
    let mut cross = vec![0.0; ws.len()];
    for g in &bogies {
        let xb = frame_x(g);
        for i in g.wheelsets.iter().map(|i| i.index()) {
            cross[i] = g_body * 1e-3 * (xb - mid) + g_bogie * 1e-3 * (ws[i].position[0] - xb);
        }
    }
    let mut lines = vec![format!(
        "on a twist of {g_body} ‰ over the bogie-centre distance (about x = {mid:.3} m) and {g_bogie} ‰ over each bogie's wheelbase (about its frame), cross-levels:"
    )];
    let mut order: Vec<&Bogie> = bogies.iter().collect();
    order.sort_by(|a, b| frame_x(b).total_cmp(&frame_x(a)));
    for g in order {
        let xb = frame_x(g);
        lines.push(format!(
            "  bogie {:<12} x = {:7.3} m: {:+8.3} mm at its centre",
            bodies[g.frame.index()].name,
            xb,
            mm(g_body * 1e-3 * (xb - mid))
        ));
        let mut members: Vec<usize> = g.wheelsets.iter().map(|i| i.index()).collect();
        members.sort_by(|&a, &b| ws[b].position[0].total_cmp(&ws[a].position[0]));
        for i in members {
            lines.push(format!(
                "    {:<12} x = {:7.3} m: {:+8.3} mm",
                ws[i].name,
                ws[i].position[0],
                mm(cross[i])
            ));
        }
    }
    Ok((cross, lines))
}

/// The smallest and largest of `xs` (infinite ends for none).
fn x_range(xs: impl IntoIterator<Item = f64>) -> (f64, f64) {
    xs.into_iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
            (l.min(x), h.max(x))
        })
}

/// `'name' at x = … m` for a body or wheelset named `name` at `x` \[m\], in the errors.
fn named_at(name: &str, x: f64) -> String {
    format!("'{name}' at x = {x:.3} m")
}

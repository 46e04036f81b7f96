//! `railsim statics [VEHICLE]`: a vehicle's static equilibrium on level track (the wheel loads,
//! and with `--elements` every force element's static force) and, with `--twist-permille`, its
//! wheels' unloading on a uniformly twisted track (`VehicleModel::static_equilibrium_on`,
//! docs/models/vehicle.md "Statics").

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Result, bail};
use clap::Args;

use railsim_vehicle::{DofKind, VehicleModel};

/// The built-in vehicle, from the repository this binary was built in.
pub const DEFAULT_VEHICLE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../vehicles/manchester_vehicle1.toml"
);

/// \[‰\] the largest twist `--twist-permille` takes.
const MAX_TWIST_PERMILLE: f64 = 50.0;

#[derive(Args)]
pub struct StaticsArgs {
    /// Vehicle file; default: the built-in vehicles/manchester_vehicle1.toml.
    pub vehicle: Option<PathBuf>,
    /// Track twist g (‰: mm of cross-level per metre along the track): the cross-level
    /// c(x) = g (x − x̄) about the middle x̄ of the end wheelsets, the left rail c/2 up and the
    /// right c/2 down under the wheels' running circles; positive: the left rail rises toward
    /// the front (+x). Reports each wheel's unloading ΔQ/Q0 against --limit. One twist over
    /// the whole vehicle: EN 14363 twists a bogie's wheelbase and the bogie-centre distance by
    /// different amounts (larger on the short base), which this does not reproduce.
    #[arg(long)]
    pub twist_permille: Option<f64>,
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
    if let Some(g) = a.twist_permille
        && !(g.is_finite() && g.abs() <= MAX_TWIST_PERMILLE)
    {
        bail!(
            "--twist-permille: expected a number from -{MAX_TWIST_PERMILLE} to {MAX_TWIST_PERMILLE}, found {g}"
        );
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
    let Some(g) = a.twist_permille else {
        return Ok(ExitCode::SUCCESS);
    };
    let xs: Vec<f64> = v.wheelsets().iter().map(|w| w.position[0]).collect();
    let (lo, hi) = xs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
            (l.min(*x), h.max(*x))
        });
    // a wheelset held vertically cannot follow its rails: its support would just press it
    if let Some(w) = v
        .wheelsets()
        .iter()
        .find(|w| w.frozen[DofKind::Z.index()] || w.frozen[DofKind::Roll.index()])
    {
        bail!(
            "--twist-permille: wheelset '{}' of vehicle '{}' has its z or roll frozen, so it cannot follow a twisted track",
            w.name,
            v.name()
        );
    }
    if hi <= lo {
        bail!(
            "--twist-permille: vehicle '{}' has no two wheelsets at different x: a uniform twist needs a wheelbase",
            v.name()
        );
    }
    let mid = 0.5 * (lo + hi);
    let cross = |x: f64| g * 1e-3 * (x - mid);
    let heights: Vec<[f64; 2]> = xs
        .iter()
        .map(|&x| [0.5 * cross(x), -0.5 * cross(x)])
        .collect();
    let twisted = v.static_equilibrium_on(&heights)?;
    outln!(
        "on a twist of {g} ‰ (cross-level {:+.2} mm at the front wheelset, {:+.2} mm at the rear):",
        cross(hi) * 1e3,
        cross(lo) * 1e3
    );
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

//! The Manchester contact benchmark A-2.2 (42 cases, 10 kN per wheel) against CONTACT's exact
//! half-space solution (`tests/reference/mbench_a22`).

use railsim_contact::contact_format::{ContactRow, parse_cases_csv, solve_case};
use railsim_contact::{
    ContactModelKind, ContactOptions, ContactWorkspace, Tangential, WheelRailContact,
};

use crate::common::{Table, mbench_contact, repo, tolerances};

/// Our patches for every reference case, in CONTACT's conventions.
pub fn run_all(model: ContactModelKind, step: f64) -> Vec<(usize, Vec<ContactRow>)> {
    run_all_with(&mbench_contact(model, step))
}

/// As [`run_all`], with a configured contact.
pub fn run_all_with(contact: &WheelRailContact) -> Vec<(usize, Vec<ContactRow>)> {
    let text = std::fs::read_to_string(repo("tests/reference/mbench_a22/reference.csv")).unwrap();
    let cases = parse_cases_csv(&text, "reference.csv").unwrap();
    let mut ws = ContactWorkspace::new();
    let mut rows = Vec::new();
    let mut out = Vec::new();
    for (i, (_, case)) in cases.iter().enumerate() {
        let solved = solve_case(contact, case, &mut ws, &mut rows)
            .unwrap_or_else(|e| panic!("case {} ({:?} y={}): {e}", i + 1, case.side, case.y_ws_mm));
        // every case carries its load: the comparisons below assume it
        if let Some(fz) = case.fz_target_n {
            assert!(
                solved.load_residual_n.abs() <= railsim_contact::LOAD_RESIDUAL_NOTICE * fz,
                "case {} ({:?} y={}): the load is missed by {} N",
                i + 1,
                case.side,
                case.y_ws_mm,
                solved.load_residual_n
            );
        }
        out.push((i, rows.clone()));
    }
    out
}

/// The patch that corresponds to CONTACT's (main) patch: the one with the largest normal force.
fn main_patch(rows: &[ContactRow]) -> &ContactRow {
    rows.iter()
        .max_by(|a, b| a.fn_n.total_cmp(&b.fn_n))
        .expect("at least one patch")
}

/// \[mm\] position on the rail of region row `g` of the regions table (its patch's reference
/// point plus the region's pressure centre along the patch).
fn region_position(regions: &Table, g: usize) -> f64 {
    regions.f(g, "ycp_r_patch_mm") + regions.f(g, "s_pn_mm")
}

/// Our patch nearest on the rail to position `y_r` \[mm\].
fn nearest_patch(rows: &[ContactRow], y_r: f64) -> &ContactRow {
    rows.iter()
        .min_by(|a, b| {
            (a.ycp_r_mm - y_r)
                .abs()
                .total_cmp(&(b.ycp_r_mm - y_r).abs())
        })
        .expect("at least one patch")
}

/// Index of the reference row for a side and y in the regions table.
fn regions_of(reg: &Table, side: &str, y: f64) -> Vec<usize> {
    (0..reg.rows.len())
        .filter(|&r| reg.s(r, "side") == side && (reg.f(r, "y_ws_mm") - y).abs() < 1e-9)
        .collect()
}

/// `stripes` at default settings (FaStrip per strip): the acceptance criteria, with no
/// exception since each strip takes the Kalker coefficients and flexibilities of its own
/// ellipse (until then the right wheel at y = 0.5 mm had Fs 13.4 % low and was listed as a
/// known deviation; docs/validation.md §1).
#[test]
fn stripes_matches_contact_on_all_42_cases() {
    check_against_contact(&stripes_with(Tangential::Fastrip));
}

/// `stripes` with plain FASTSIM per strip (three flexibilities, CONTACT's blend): the same
/// criteria, with no exception.
#[test]
fn stripes_with_fastsim_per_strip_matches_contact_on_all_42_cases() {
    check_against_contact(&stripes_with(Tangential::Fastsim));
}

/// `stripes` with Kalker's exact tangential solution on the STRIPES pressure: the acceptance
/// criteria with no exception.
#[test]
fn stripes_with_exact_tangential_matches_contact_on_all_42_cases() {
    check_against_contact(&stripes_with(Tangential::Exact));
}

/// `stripes` at its default step with the tangential solution `tangential`.
fn stripes_with(tangential: Tangential) -> WheelRailContact {
    let mut contact = mbench_contact(
        ContactModelKind::Stripes,
        ContactOptions::default().travel.step,
    );
    contact.opts.tangential = tangential;
    contact
}

/// The acceptance criteria of issue 2 on all 42 cases.
fn check_against_contact(contact: &WheelRailContact) {
    let tol = tolerances("mbench_a22", "stripes");
    let reference = Table::read("tests/reference/mbench_a22/reference.csv");
    let regions = Table::read("tests/reference/mbench_a22/regions.csv");
    let ours = run_all_with(contact);
    let mut failures = Vec::new();
    eprintln!(
        "{:>5} {:>5} | {:>8} {:>8} | {:>7} {:>7} | {:>7} {:>7} | {:>7} {:>7} | {:>7} {:>7} | {:>7} {:>7} | np",
        "side",
        "y",
        "ycp_ref",
        "ycp",
        "dlt_ref",
        "dlt",
        "pen_ref",
        "pen",
        "fn_ref",
        "fn",
        "fx_ref",
        "fx",
        "fs_ref",
        "fs"
    );
    for (i, rows) in &ours {
        let r = *i;
        let side = reference.s(r, "side").to_string();
        let y = reference.f(r, "y_ws_mm");
        let fn_ref = reference.f(r, "fn_N");
        let regs = regions_of(&regions, &side, y);
        if rows.is_empty() {
            failures.push(format!("{side} y={y}: no patch"));
            continue;
        }
        let m = main_patch(rows);
        eprintln!(
            "{:>5} {:>5} | {:8.3} {:8.3} | {:7.4} {:7.4} | {:7.4} {:7.4} | {:7.0} {:7.0} | {:7.0} {:7.0} | {:7.0} {:7.0} | {}",
            side,
            y,
            reference.f(r, "ycp_r_mm"),
            m.ycp_r_mm,
            reference.f(r, "delttr_rad"),
            m.delttr_rad,
            reference.f(r, "pen_mm"),
            m.pen_mm,
            fn_ref,
            m.fn_n,
            reference.f(r, "fx_N"),
            m.fx_n,
            reference.f(r, "fs_N"),
            m.fs_n,
            rows.len()
        );
        if regs.len() > 1 {
            // CONTACT merged several regions into one patch: compare region by region, each
            // region with our patch nearest to it on the rail.
            for &g in &regs {
                let y_reg = region_position(&regions, g);
                let fn_reg = regions.f(g, "fn_N");
                let p = nearest_patch(rows, y_reg);
                eprintln!(
                    "      region {}: y_r {:.2} (ours {:.2}), Fn {:.0} (ours {:.0})",
                    regions.s(g, "region"),
                    y_reg,
                    p.ycp_r_mm,
                    fn_reg,
                    p.fn_n
                );
                if (p.ycp_r_mm - y_reg).abs() > 1.5 {
                    failures.push(format!(
                        "{side} y={y} region {}: no patch of ours near y_r = {y_reg:.2} mm",
                        regions.s(g, "region")
                    ));
                } else if (p.fn_n - fn_reg).abs() > tol["region_fn_rel"] * fn_reg {
                    failures.push(format!(
                        "{side} y={y} region {}: Fn {:.0} vs {:.0}",
                        regions.s(g, "region"),
                        p.fn_n,
                        fn_reg
                    ));
                }
            }
            continue;
        }
        let checks = [
            (
                "ycp_r",
                m.ycp_r_mm,
                reference.f(r, "ycp_r_mm"),
                tol["ycp_r_abs_mm"],
            ),
            (
                "delttr",
                m.delttr_rad,
                reference.f(r, "delttr_rad"),
                tol["delttr_abs_rad"],
            ),
            (
                "pen",
                m.pen_mm,
                reference.f(r, "pen_mm"),
                tol["pen_rel"] * reference.f(r, "pen_mm"),
            ),
        ];
        for (name, got, want, t) in checks {
            if (got - want).abs() > t {
                failures.push(format!(
                    "{side} y={y}: {name} {got:.4} vs {want:.4} (tol {t:.4})"
                ));
            }
        }
        for (name, got, want) in [
            ("fx", m.fx_n, reference.f(r, "fx_N")),
            ("fs", m.fs_n, reference.f(r, "fs_N")),
        ] {
            let t = (tol["force_rel"] * want.abs()).max(tol["force_abs_of_fn"] * fn_ref);
            if (got - want).abs() > t {
                failures.push(format!(
                    "{side} y={y}: {name} {got:.0} vs {want:.0} (tol {t:.0})"
                ));
            }
        }
    }
    // The right wheel's jump to the flange between y = 6.0 and 6.5 mm.
    let angle_at = |side: &str, y: f64| {
        let (_, rows) = ours
            .iter()
            .find(|(i, _)| {
                reference.s(*i, "side") == side && (reference.f(*i, "y_ws_mm") - y).abs() < 1e-9
            })
            .unwrap();
        main_patch(rows).delttr_rad
    };
    let (a6, a65) = (angle_at("right", 6.0), angle_at("right", 6.5));
    if !(a6 > -0.6 && a65 < -0.9) {
        failures.push(format!(
            "right wheel flange jump: contact angle {a6:.3} rad at 6.0 mm, {a65:.3} rad at 6.5 mm"
        ));
    }
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// `halfspace` on the benchmark: penetration within 2 % of CONTACT (issue 2) and the peak
/// pressure within 5 % (worst 2.8 %, on the flange cases).
#[test]
fn halfspace_penetration_matches_contact() {
    let tol = tolerances("mbench_a22", "halfspace");
    let reference = Table::read("tests/reference/mbench_a22/reference.csv");
    let ours = run_all(
        ContactModelKind::Halfspace,
        ContactOptions::default().travel.step,
    );
    let mut failures = Vec::new();
    for (r, rows) in &ours {
        let side = reference.s(*r, "side");
        let y = reference.f(*r, "y_ws_mm");
        let pen_ref = reference.f(*r, "pen_mm");
        let m = main_patch(rows);
        eprintln!(
            "{side:>5} {y:>5} pen {pen_ref:.5} ours {:.5} ({:+.2} %)  fn {:.0}/{:.0} fx {:.0}/{:.0} fs {:.0}/{:.0} pmax {:.0}/{:.0} np {}",
            m.pen_mm,
            100.0 * (m.pen_mm / pen_ref - 1.0),
            reference.f(*r, "fn_N"),
            m.fn_n,
            reference.f(*r, "fx_N"),
            m.fx_n,
            reference.f(*r, "fs_N"),
            m.fs_n,
            reference.f(*r, "pmax_N_mm2"),
            m.pmax_n_mm2,
            rows.len()
        );
        if (m.pen_mm - pen_ref).abs() > tol["pen_rel"] * pen_ref {
            failures.push(format!("{side} y={y}: pen {:.5} vs {pen_ref:.5}", m.pen_mm));
        }
        let pmax_ref = reference.f(*r, "pmax_N_mm2");
        if (m.pmax_n_mm2 - pmax_ref).abs() > tol["pmax_rel"] * pmax_ref {
            failures.push(format!(
                "{side} y={y}: pmax {:.0} vs {pmax_ref:.0} N/mm²",
                m.pmax_n_mm2
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// `halfspace` with the exact tangential solution is the counterpart of CONTACT's own solution
/// (exact normal and tangential problems in one plane per patch, the reference point's, with its
/// creepages; since stop 34): its creep forces within 0.005 Fn of CONTACT's on every
/// single-region case, and within 0.01 of the wheel's Fn on each region of the right wheel at
/// y = 5 mm, which CONTACT solves as one patch and railsim as two. Found 0.0018 Fn (Fx; 0.0024
/// in stop 34) and 0.0009 Fn (Fs), and 0.0066 on the regions. With the rigid pair's
/// creepages and plane (before stop 34): 0.0110 Fn in Fx and 0.0107 Fn in Fs.
#[test]
fn halfspace_with_exact_tangential_matches_contacts_creep_forces() {
    check_halfspace_creep_forces(Tangential::Exact, "halfspace_exact");
}

/// The creepages of CONTACT's format on CONTACT's reference speed: with `halfspace` and the exact
/// tangential solution, whose reference point is CONTACT's, `ceta` and `cphi` of every
/// single-region case within 0.5 % of the reference (where they exceed 1e-4 and 1e-6 rad/mm).
/// Found 0.32 % and 0.13 %; 1.27 % and 1.30 % with railsim's forward speed (before stop 39).
#[test]
fn contact_format_creepages_are_on_contacts_reference_speed() {
    let tol = tolerances("mbench_a22", "halfspace_exact")["creepage_rel"];
    let reference = Table::read("tests/reference/mbench_a22/reference.csv");
    let mut contact = mbench_contact(
        ContactModelKind::Halfspace,
        ContactOptions::default().travel.step,
    );
    contact.opts.tangential = Tangential::Exact;
    let (mut failures, mut worst) = (Vec::new(), [0.0f64; 2]);
    for (r, rows) in &run_all_with(&contact) {
        let (side, y) = (reference.s(*r, "side"), reference.f(*r, "y_ws_mm"));
        if side == "right" && y == 5.0 {
            continue;
        }
        let m = main_patch(rows);
        for (k, name, got, floor) in [
            (0, "ceta", m.ceta, 1e-4),
            (1, "cphi_rad_mm", m.cphi_rad_mm, 1e-6),
        ] {
            let want = reference.f(*r, name);
            if want.abs() < floor {
                continue;
            }
            let rel = (got / want - 1.0).abs();
            worst[k] = worst[k].max(rel);
            if rel > tol * crate::common::tol_scale() {
                failures.push(format!("{side} y={y}: {name} {got:.5e} against {want:.5e}"));
            }
        }
    }
    eprintln!(
        "largest relative differences: ceta {:.4}, cphi {:.4}",
        worst[0], worst[1]
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `halfspace` at its defaults: FaStrip per grid row, each row with the Kalker coefficients and
/// flexibilities of its own ellipse and its spin split about CONTACT's reference point (since
/// stop 37). Its creep forces within 0.02 Fn (Fx) and 0.006 Fn (Fs) of CONTACT's on every
/// single-region case, and within 0.02 of the wheel's Fn on each region of the right wheel at
/// y = 5 mm. Found 0.0162 Fn (Fx, pure spin at y = 0: the balance of the rows' spin slip),
/// 0.0029 Fn (Fs) and 0.0066 on the regions. With FASTSIM per row on the patch's equivalent
/// ellipse, split about the zone's rigid pair (before stop 37): Fx 0.0091 Fn, Fs 0.0237 Fn
/// (right wheel at y = 0.5 mm: −2345 N against −2579 N).
#[test]
fn halfspace_rows_match_contacts_creep_forces() {
    check_halfspace_creep_forces(Tangential::Fastrip, "halfspace_rows");
}

/// `halfspace` with the tangential solution `tangential` against CONTACT's creep forces, with
/// the bounds of section `section` of the tolerances.
fn check_halfspace_creep_forces(tangential: Tangential, section: &str) {
    let tol = tolerances("mbench_a22", section);
    let reference = Table::read("tests/reference/mbench_a22/reference.csv");
    let regions = Table::read("tests/reference/mbench_a22/regions.csv");
    let mut contact = mbench_contact(
        ContactModelKind::Halfspace,
        ContactOptions::default().travel.step,
    );
    contact.opts.tangential = tangential;
    let mut failures = Vec::new();
    let mut worst = [0.0f64; 3];
    for (r, rows) in &run_all_with(&contact) {
        let (side, y) = (reference.s(*r, "side"), reference.f(*r, "y_ws_mm"));
        let fn_ref = reference.f(*r, "fn_N");
        let regs = regions_of(&regions, side, y);
        // (what, ours, CONTACT's, bound, which worst)
        let mut checks = Vec::new();
        if regs.len() > 1 {
            for &g in &regs {
                let p = nearest_patch(rows, region_position(&regions, g));
                let bound = tol["region_force_abs_of_fn"] * fn_ref;
                checks.push(("region fx", p.fx_n, regions.f(g, "fx_N"), bound, 2));
                checks.push(("region fs", p.fs_n, regions.f(g, "fs_N"), bound, 2));
            }
        } else {
            let m = main_patch(rows);
            let (bx, bs) = (tol["fx_abs_of_fn"] * fn_ref, tol["fs_abs_of_fn"] * fn_ref);
            checks.push(("fx", m.fx_n, reference.f(*r, "fx_N"), bx, 0));
            checks.push(("fs", m.fs_n, reference.f(*r, "fs_N"), bs, 1));
        }
        for (what, got, want, bound, k) in checks {
            eprintln!("{side:>5} {y:>5} {what}: {got:8.1} against {want:8.1} N");
            worst[k] = worst[k].max((got - want).abs() / fn_ref);
            if (got - want).abs() > bound {
                failures.push(format!("{side} y={y}: {what} {got:.1} against {want:.1} N"));
            }
        }
    }
    eprintln!(
        "largest differences: Fx {:.4}, Fs {:.4}, regions {:.4} Fn",
        worst[0], worst[1], worst[2]
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn wheelset_frame_forces_follow_contacts_convention() {
    // CONTACT reports each wheel's total force in track and in wheelset coordinates; our
    // track-to-wheelset rotation applied to its track forces must give its wheelset forces
    // (conventions: CONTACT's frame is ours turned by pi about x, forces on the rail).
    let reference = Table::read("tests/reference/mbench_a22/reference.csv");
    let text = std::fs::read_to_string(repo("tests/reference/mbench_a22/reference.csv")).unwrap();
    let cases = parse_cases_csv(&text, "reference.csv").unwrap();
    let contact = crate::common::mbench_contact(ContactModelKind::Stripes, 0.5e-3);
    let mut ws = ContactWorkspace::new();
    let mut rows = Vec::new();
    for (r, (_, case)) in cases.iter().enumerate() {
        let (pose, _) = case.to_railsim();
        let wheel = |c: &str| {
            // force on the wheel, railsim axes, from CONTACT's force on the rail
            let v = [
                reference.f(r, &format!("fx_{c}_N")),
                reference.f(r, &format!("fy_{c}_N")),
                reference.f(r, &format!("fz_{c}_N")),
            ];
            [-v[0], v[1], v[2]]
        };
        let (tr, wsf) = (wheel("tr"), wheel("ws"));
        let mapped = pose.track_to_wheelset(tr);
        for k in 0..3 {
            assert!(
                (mapped[k] - wsf[k]).abs() < 1e-6 * 1e4,
                "case {r}: component {k}: {} vs {}",
                mapped[k],
                wsf[k]
            );
        }
        // Our own patches: the wheelset-frame force is the rotated track-frame force, and the
        // vertical component matches CONTACT's to 0.5 % (load prescribed in the track frame).
        solve_case(&contact, case, &mut ws, &mut rows).unwrap();
        let mut ft = [0.0; 3];
        let mut fw = [0.0; 3];
        for p in &ws.patches {
            for k in 0..3 {
                ft[k] += p.force_track[k];
                fw[k] += p.force_wheelset[k];
            }
        }
        let m = pose.track_to_wheelset(ft);
        for k in 0..3 {
            assert!((m[k] - fw[k]).abs() < 1e-6, "case {r}: {k}");
        }
        assert!(
            (fw[2] - wsf[2]).abs() < 0.005 * wsf[2].abs(),
            "case {r}: Fz_ws {} vs {}",
            fw[2],
            wsf[2]
        );
    }
}

/// The creepages reported with each patch are those of its reference point, where its position,
/// angle and force axes are reported (CONTACT's `cksi`, `ceta`, `cphi`), on all 42 cases but the
/// merged right wheel at y = 5 mm: spin within 3 %, lateral creepage within 3 %, longitudinal
/// within 10 % (of at least 1e-4). Found 1.3 %, 1.3 % and 7.6 % (right, y = 0.5 mm: the
/// longitudinal creepage there is a small difference of rolling radii across a 14 mm wide
/// patch). Before stop 24 the rigid pair's creepages were reported with the reference point's
/// axes: spin 18 % off on the conformal tread at y = 0.5 mm, longitudinal 78 % at y = 0.
#[test]
fn reported_creepages_are_the_reference_points() {
    let reference = Table::read("tests/reference/mbench_a22/reference.csv");
    let ours = run_all(
        ContactModelKind::Stripes,
        ContactOptions::default().travel.step,
    );
    let mut failures = Vec::new();
    for (r, rows) in &ours {
        let (side, y) = (reference.s(*r, "side"), reference.f(*r, "y_ws_mm"));
        if side == "right" && y == 5.0 {
            continue;
        }
        let m = main_patch(rows);
        for (name, got, floor, tol) in [
            ("cksi", m.cksi, 1e-4, 0.10),
            ("ceta", m.ceta, 1e-4, 0.03),
            ("cphi_rad_mm", m.cphi_rad_mm, 1e-6, 0.03),
        ] {
            let want = reference.f(*r, name);
            if (got - want).abs() > tol * crate::common::tol_scale() * want.abs().max(floor) {
                failures.push(format!("{side} y={y}: {name} {got:.4e} against {want:.4e}"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

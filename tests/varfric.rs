//! Friction that varies across the rail head with the contact angle, against CONTACT's own
//! example `mbench_a22_varfric` (`tests/reference/mbench_a22_varfric`): the Manchester benchmark's
//! right wheel with μ = 0.3 up to a contact angle of 10°, 0.2 from 20° on, linear in between.

use railsim_contact::contact_format::{ContactCase, ContactRow, solve_case};
use railsim_contact::{
    ContactModelKind, ContactOptions, ContactWorkspace, Friction, Side, Tangential,
    WheelRailContact,
};

use crate::common::{Table, mbench_pair, tolerances};

const CASE: &str = "mbench_a22_varfric";

/// CONTACT's friction variation in railsim's terms: its α = −20°, −10° on the right rail are
/// contact angles of 20° and 10°.
fn varfric() -> Friction {
    Friction::ByContactAngle {
        angle: vec![10f64.to_radians(), 20f64.to_radians()],
        mu: vec![0.3, 0.2],
    }
}

fn contact(tangential: Tangential) -> WheelRailContact {
    let mut pair = mbench_pair();
    pair.friction = varfric();
    let mut opts = ContactOptions {
        model: ContactModelKind::Stripes,
        ..Default::default()
    };
    opts.tangential = tangential;
    WheelRailContact::new(pair, opts).unwrap()
}

/// The reference rows with results (cases 1–4: y = 0, 0.5, 5 (two patches), 5.5 mm), grouped
/// by case: (case, its input, its rows' indices).
fn reference_cases(t: &Table) -> Vec<(usize, ContactCase, Vec<usize>)> {
    let mut out: Vec<(usize, ContactCase, Vec<usize>)> = Vec::new();
    for r in 0..t.rows.len() {
        let case: usize = t.s(r, "case").parse().unwrap();
        // cases 5 and 7 have no results in the file; case 6 is a variant whose input the
        // example file we know does not give (SOURCE.md)
        if case > 4 {
            continue;
        }
        if let Some(last) = out.last_mut()
            && last.0 == case
        {
            last.2.push(r);
            continue;
        }
        assert_eq!(t.s(r, "side"), "right");
        out.push((
            case,
            ContactCase {
                side: Side::Right,
                y_ws_mm: t.f(r, "y_ws_mm"),
                yaw_ws_rad: t.f(r, "yaw_ws_rad"),
                roll_ws_rad: t.f(r, "roll_ws_rad"),
                vpitch_rad_s: t.f(r, "vpitch_rad_s"),
                z_ws_mm: None,
                fz_target_n: Some(10_000.0),
                speed_mm_s: 2000.0,
            },
            vec![r],
        ));
    }
    out
}

/// Our patch nearest on the rail to reference row `r`.
fn matching<'a>(rows: &'a [ContactRow], t: &Table, r: usize) -> &'a ContactRow {
    let y = t.f(r, "ycp_r_mm");
    rows.iter()
        .min_by(|a, b| (a.ycp_r_mm - y).abs().total_cmp(&(b.ycp_r_mm - y).abs()))
        .expect("a patch")
}

/// Solve every reference case with `tangential` and check:
/// - Fx and Fs against CONTACT (within `rel` or `abs_fn`·Fn), with no exception since stop 36
///   (until then FaStrip's Fs on the tread at y = 0.5 mm was allowed 14 %, the base benchmark's
///   known deviation);
/// - the friction a patch in full slip uses, |Ft|/Fn: where our patch's contact angle is
///   CONTACT's (within 0.01 rad), CONTACT's within `mu_abs` (the change of μ over 1° of the
///   ramp); CONTACT takes one μ per patch at its contact angle, we take each strip's own;
/// - the tread-side patch at y = 5 mm, whose angle CONTACT gives as −0.248 rad although the
///   rail's slope at its reference point is −0.13 rad (ours), carries μ = 0.3 (within
///   `mu_abs`): every strip lies below 10°.
fn check(tangential: Tangential, section: &str) {
    let tol = tolerances(CASE, section);
    let t = Table::read(&format!("tests/reference/{CASE}/reference.csv"));
    let c = contact(tangential);
    let mut ws = ContactWorkspace::new();
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    let cases = reference_cases(&t);
    assert_eq!(cases.len(), 4);
    for (case, input, refs) in &cases {
        solve_case(&c, input, &mut ws, &mut rows).unwrap();
        assert_eq!(rows.len(), refs.len(), "case {case}: {rows:?}");
        for &r in refs {
            let ours = matching(&rows, &t, r);
            let (fn_r, fx_r, fs_r) = (t.f(r, "fn_N"), t.f(r, "fx_N"), t.f(r, "fs_N"));
            let mu_r = fx_r.hypot(fs_r) / fn_r;
            let mu_ours = ours.fx_n.hypot(ours.fs_n) / ours.fn_n;
            let saturated = t.f(r, "nadh") == 0.0;
            let same_angle = (ours.delttr_rad - t.f(r, "delttr_rad")).abs() < 0.01;
            eprintln!(
                "{section} case {case} y {} patch at {:.2} mm ({:.2} mm), angle {:.4} ({:.4}) rad: \
                 Fn {:.0} ({fn_r:.0}) Fx {:.1} ({fx_r:.1}) Fs {:.1} ({fs_r:.1}) N; |Ft|/Fn {mu_ours:.4} \
                 ({mu_r:.4}{})",
                input.y_ws_mm,
                ours.ycp_r_mm,
                t.f(r, "ycp_r_mm"),
                ours.delttr_rad,
                t.f(r, "delttr_rad"),
                ours.fn_n,
                ours.fx_n,
                ours.fs_n,
                if saturated { ", full slip" } else { "" }
            );
            for (q, o, rf) in [("fx", ours.fx_n, fx_r), ("fs", ours.fs_n, fs_r)] {
                let bound = (tol["rel"] * rf.abs()).max(tol["abs_fn"] * fn_r);
                if (o - rf).abs() > bound {
                    failures.push(format!(
                        "case {case} y {}: {q} {o:.1} N against {rf:.1} N (bound {bound:.1} N)",
                        input.y_ws_mm
                    ));
                }
            }
            if saturated {
                let want = if same_angle { mu_r } else { 0.3 };
                if (mu_ours - want).abs() > tol["mu_abs"] {
                    failures.push(format!(
                        "case {case} y {}: |Ft|/Fn {mu_ours:.4} against {want:.4}",
                        input.y_ws_mm
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn stripes_with_varying_friction_matches_contact() {
    check(Tangential::Fastrip, "stripes");
}

#[test]
fn stripes_exact_with_varying_friction_matches_contact() {
    check(Tangential::Exact, "exact");
}

//! The contact-point jump of S1002 on UIC60 1:40 near y = 0.22 mm (contact-theory note §6.2):
//! there the left wheel's interpenetration is one zone about 24 mm wide along the rail, flat to
//! within 5 µm, with two wells of nearly equal depth (at a height that carries about 100 kN:
//! wells 75.06 and 74.92 µm deep, the gap between them 70.62 µm). As the wheelset moves laterally
//! the deeper well changes. The half-space solution is one 21 mm wide patch whose load varies
//! smoothly (102.7 kN at y = 0.20 mm, 106.4 kN at 0.25 mm); STRIPES, solving the whole zone, must
//! do the same, and so must the Hertz models with their wells' shares (docs/models/contact.md
//! §4.1): with the deepest well alone `polach` jumped from 94.8 to 52.2 kN (48 % in one step).

use railsim_contact::{ContactModelKind, ContactWorkspace, Side, WheelsetPose};

use crate::common::{mbench_contact, rolling_30_m_s, tol_scale};

/// Vertical load of the left wheel at lateral position `y` \[m\] and the fixed height of the test.
fn load(c: &railsim_contact::WheelRailContact, y: f64, ws: &mut ContactWorkspace) -> f64 {
    let pose = WheelsetPose {
        y,
        z: -0.2514e-3,
        roll: 0.0,
        yaw: 0.0,
    };
    c.evaluate(Side::Left, &pose, &rolling_30_m_s(), ws)
        .unwrap()
        .force_track[2]
}

#[test]
fn the_contact_jump_gives_no_jump_in_load() {
    let stripes = mbench_contact(ContactModelKind::Stripes, 1.0e-3);
    let polach = mbench_contact(ContactModelKind::Polach, 1.0e-3);
    let mut ws = ContactWorkspace::new();
    let (mut worst, mut worst_hertz) = (0.0f64, 0.0f64);
    let mut prev: Option<(f64, f64)> = None;
    for i in 10..=40 {
        let y = i as f64 * 0.01e-3;
        let (f, h) = (load(&stripes, y, &mut ws), load(&polach, y, &mut ws));
        assert!(f > 50e3, "y = {y}: {f} N");
        if let Some((f0, h0)) = prev {
            worst = worst.max((f - f0).abs() / f0);
            worst_hertz = worst_hertz.max((h - h0).abs() / h0);
        }
        prev = Some((f, h));
    }
    eprintln!(
        "0.01 mm steps from y = 0.10 to 0.40 mm: largest change of the load {:.2} % (stripes), \
         {:.1} % (polach)",
        worst * 100.0,
        worst_hertz * 100.0
    );
    assert!(
        worst < 0.02 * tol_scale(),
        "stripes: {:.2} %",
        worst * 100.0
    );
    assert!(
        worst_hertz < 0.02 * tol_scale(),
        "polach: {:.2} %",
        worst_hertz * 100.0
    );
}

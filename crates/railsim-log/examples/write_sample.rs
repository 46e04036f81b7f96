//! Writes a small deterministic sample log with every railsim message type.
//!
//! `cargo run -p railsim-log --example write_sample -- OUT.mcap`
//!
//! 500 steps of 1 ms. Per step: `/bodies/wheelset_0` and `/bodies/bogie_0` (1 each), `/tf` (2),
//! `/contact/0/left` (2 patches), `/contact/0/right` (1 patch), `/wheelsets/0` (1). The CI script
//! checks these counts and some values with the Python `mcap` package
//! (`tests/python/check_log.py`); keep the two in step.

use std::f64::consts::PI;

use railsim_log::{
    BodyState, Creepages, FrameTransform, LogHeader, LogWriter, PatchMessage, Quaternion, Side,
    WheelsetMessage, WriterOptions, ns_to_s, step_time_ns, topics, wear_number,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .ok_or("usage: write_sample OUT.mcap")?;
    let header = LogHeader::new()
        .scene_entry("name", "sample")
        .scene_entry("speed_m_s", "55")
        .scene_entry("dt_ns", "1000000")
        .scene_entry("steps", "500")
        .scene_toml("name = \"sample\"\nspeed_m_s = 55.0\n");
    let mut log = LogWriter::create(&out, &header, WriterOptions::default())?;
    let bodies = ["wheelset_0", "bogie_0"];
    let body_channels = bodies
        .iter()
        .map(|b| log.channel::<BodyState>(&topics::body(b)))
        .collect::<Result<Vec<_>, _>>()?;
    let tf = log.channel::<FrameTransform>(topics::TF)?;
    let left = log.channel::<PatchMessage>(&topics::contact(0, Side::Left))?;
    let right = log.channel::<PatchMessage>(&topics::contact(0, Side::Right))?;
    let wheelset = log.channel::<WheelsetMessage>(&topics::wheelset(0))?;

    let dt_ns = 1_000_000;
    for step in 0..500u64 {
        let t_ns = step_time_ns(step, dt_ns)?;
        let t_s = ns_to_s(t_ns);
        let y = 1e-3 * (2.0 * PI * 2.0 * t_s).sin();
        for (k, (name, channel)) in bodies.iter().zip(&body_channels).enumerate() {
            let half_yaw = 1e-3 * (2.0 * PI * 2.0 * t_s).cos() * 0.5;
            let state = BodyState {
                t_s,
                name: (*name).to_owned(),
                position: [55.0 * t_s + 2.5 * k as f64, y, 0.46 + 0.5 * k as f64],
                orientation: Quaternion {
                    x: 0.0,
                    y: 0.0,
                    z: half_yaw.sin(),
                    w: half_yaw.cos(),
                },
                velocity: [55.0, 2e-3 * PI * 2.0 * (2.0 * PI * 2.0 * t_s).cos(), 0.0],
                angular_velocity: [0.0, 55.0 / 0.46 * (k == 0) as u8 as f64, 0.0],
            };
            log.write(channel, t_ns, &state)?;
            log.write(&tf, t_ns, &FrameTransform::from_body(t_ns, "track", &state))?;
        }
        for (channel, side, patches) in [(&left, Side::Left, 2u32), (&right, Side::Right, 1)] {
            for patch in 0..patches {
                let creepages = Creepages {
                    xi: 1e-4 * (patch + 1) as f64,
                    eta: -2e-4,
                    phi_per_m: 0.01,
                };
                let (fx_n, fy_n) = (-2000.0 * (patch + 1) as f64, 4000.0 + y * 1e6);
                let message = PatchMessage {
                    t_s,
                    wheelset: 0,
                    side,
                    patch,
                    y_rail_m: y + 0.01 * patch as f64,
                    y_wheel_m: y,
                    contact_angle_rad: 0.025 + 0.5 * patch as f64,
                    penetration_m: 8e-5,
                    creepages,
                    fn_n: 54_500.0 / patches as f64,
                    fx_n,
                    fy_n,
                    mz_nm: 1.5,
                    wear_number_n: wear_number(fx_n, fy_n, &creepages),
                    weight: None,
                };
                log.write(channel, t_ns, &message)?;
            }
        }
        let q = 54_500.0;
        let message = WheelsetMessage {
            t_s,
            wheelset: 0,
            y_left_n: 1000.0 + y * 1e6,
            q_left_n: q,
            y_right_n: -1000.0,
            q_right_n: q,
            y_over_q_left: (1000.0 + y * 1e6) / q,
            y_over_q_right: -1000.0 / q,
            angle_of_attack_rad: 1e-3 * (2.0 * PI * 2.0 * t_s).cos(),
            wear_number_left_n: 0.0,
            wear_number_right_n: 0.0,
            rail_displacement_m: None,
        };
        log.write(&wheelset, t_ns, &message)?;
    }
    let stats = log.finish()?;
    println!(
        "wrote {} messages in {} chunks, {} bytes, to {}",
        stats.messages,
        stats.chunks,
        stats.bytes,
        stats.path.display()
    );
    for (topic, n) in &stats.per_topic {
        println!("  {topic}: {n}");
    }
    Ok(())
}

//! An evaluation allocates nothing once the workspace has grown (issue 2: "a reusable workspace so
//! that an evaluation allocates nothing"). A counting global allocator counts the allocations made
//! by this thread while a flag is set. The half-space model is excluded: it re-plans its FFT when
//! the grid size changes.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

use railsim_contact::contact_format::{manchester_benchmark_pair, parse_cases_csv, solve_case};
use railsim_contact::{ContactModelKind, ContactOptions, ContactWorkspace, WheelRailContact};

struct Counting;

static COUNT: AtomicUsize = AtomicUsize::new(0);
thread_local! {
    static ON: Cell<bool> = const { Cell::new(false) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if ON.with(|c| c.get()) {
            COUNT.fetch_add(1, Ordering::Relaxed);
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if ON.with(|c| c.get()) {
            COUNT.fetch_add(1, Ordering::Relaxed);
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn repo(rel: &str) -> std::path::PathBuf {
    std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join(rel)
}

#[test]
fn evaluations_allocate_nothing_after_warm_up() {
    // The counter works: an allocation while counting is seen.
    COUNT.store(0, Ordering::Relaxed);
    ON.with(|c| c.set(true));
    let v: Vec<u64> = std::hint::black_box(Vec::with_capacity(16));
    ON.with(|c| c.set(false));
    drop(v);
    assert!(
        COUNT.load(Ordering::Relaxed) >= 1,
        "the counting allocator saw nothing"
    );

    let pair = manchester_benchmark_pair(&repo("")).unwrap();
    let text = std::fs::read_to_string(repo("tests/reference/mbench_a22/reference.csv")).unwrap();
    let cases = parse_cases_csv(&text, "reference.csv").unwrap();
    for model in [
        ContactModelKind::Polach,
        ContactModelKind::Fastsim,
        ContactModelKind::Stripes,
    ] {
        let opts = ContactOptions {
            model,
            ..Default::default()
        };
        let contact = WheelRailContact::new(pair.clone(), opts).unwrap();
        let mut ws = ContactWorkspace::new();
        let mut rows = Vec::new();
        // Warm-up: every case once (the workspace grows to the largest), with load control.
        let mut poses = Vec::new();
        for (_, case) in &cases {
            let z = solve_case(&contact, case, &mut ws, &mut rows).unwrap().z_mm;
            let (mut pose, vel) = case.to_railsim();
            pose.z = -z * 1e-3;
            poses.push((case.side, pose, vel));
        }
        COUNT.store(0, Ordering::Relaxed);
        ON.with(|c| c.set(true));
        for (side, pose, vel) in &poses {
            contact.evaluate(*side, pose, vel, &mut ws).unwrap();
        }
        ON.with(|c| c.set(false));
        let n = COUNT.load(Ordering::Relaxed);
        assert_eq!(n, 0, "{}: {n} allocations in 42 evaluations", model.name());
    }
}

#[test]
fn a_simulation_right_hand_side_allocates_nothing_after_warm_up() {
    // The simulator's Workspace (house style: no allocation per step): Manchester vehicle 1 on
    // irregular track, eight wheels, with the default `stripes` contact (warm-started travelling)
    // and with `polach` (warm-started point search); on this thread (the wheels one after the
    // other) and on a thread of a two-thread rayon pool, as `railsim` runs it (the wheels shared
    // between the threads: both threads count).
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    for model in ["stripes", "polach"] {
        rhs_allocates_nothing(model, None);
        rhs_allocates_nothing(model, Some(&pool));
    }
}

fn rhs_allocates_nothing(model: &str, pool: Option<&rayon::ThreadPool>) {
    use railsim_ode::OdeSystem;
    use railsim_sim::dynamics::Dynamics;
    // Counted: this thread's allocations, or with a pool its threads' (not this thread's
    // hand-over of the loop to the pool, which `railsim` does once per command).
    let set = |on: bool| match pool {
        Some(p) => {
            p.broadcast(|_| ON.with(|c| c.set(on)));
        }
        None => ON.with(|c| c.set(on)),
    };
    let in_pool = |f: &mut (dyn FnMut() + Send)| match pool {
        Some(p) => p.install(f),
        None => f(),
    };
    {
        let scene = railsim_sim::Scene::from_toml_str(
            &format!(
                r#"
                vehicle = "vehicles/manchester_vehicle1.toml"
                track = "tracks/straight_irregular.toml"
                speed_kmh = 198
                duration_s = 1
                [contact]
                model = "{model}"
                "#
            ),
            "no_alloc.toml",
            &repo(""),
        )
        .unwrap();
        let sim = railsim_sim::Simulation::new(&scene).unwrap();
        let model_ = sim.model();
        let mut x = sim.initial_state().to_vec();
        let mut d = Dynamics::new(model_);
        let mut dx = vec![0.0; model_.dim()];
        in_pool(&mut || {
            for k in 0..5 {
                d.rhs(k as f64 * 1e-4, &x, &mut dx).unwrap();
            }
        });
        COUNT.store(0, Ordering::Relaxed);
        set(true);
        in_pool(&mut || {
            for k in 0..50 {
                // Small changes of state and time, as between integrator stages.
                x[0] += 1e-7;
                d.rhs(5e-4 + k as f64 * 1e-5, &x, &mut dx).unwrap();
            }
        });
        set(false);
        assert_eq!(
            COUNT.load(Ordering::Relaxed),
            0,
            "{model} (pool: {}): allocations in the right-hand side",
            pool.is_some()
        );
        assert!(dx.iter().all(|v| v.is_finite()));
        let warm: u64 = d.ws.warm_starts().map(|w| w.warm_count).sum();
        assert!(warm >= 8 * 50, "{model}: {warm} warm searches");
    }
}

//! The whole-scene query through the grid broad phase against the brute force (every pair
//! through the same kernels): the same contacts and the same times, bit for bit, on random
//! scenes and on every adversarial scene the broad phase could trip on; and the same output
//! for any thread count.

use spheresweep::query::{ContactEvent, SceneQuery, brute_force};
use spheresweep::rng::Rng;
use spheresweep::scene::Scene;
use spheresweep::{
    Accuracy, Container, Cylinder, FirstContact, Plane, QueryOptions, Sphere, SphereStore,
};

fn bits_first(v: &[Option<FirstContact>]) -> Vec<Option<(u32, spheresweep::Body)>> {
    v.iter()
        .map(|c| c.map(|c| (c.time.to_bits(), c.body)))
        .collect()
}

fn bits_events(v: &[ContactEvent]) -> Vec<(u32, u32, spheresweep::Body)> {
    v.iter()
        .map(|e| (e.time.to_bits(), e.sphere, e.other))
        .collect()
}

/// Grid against brute force, first contacts and every contact, in every mode.
fn check(scene: &Scene, t_max: f32, what: &str) {
    let mut query = SceneQuery::new();
    for mode in Accuracy::ALL {
        let options = QueryOptions::new(t_max, mode).unwrap();
        let grid = query.first_contacts(scene, options);
        let brute = brute_force::first_contacts(scene, options);
        assert_eq!(bits_first(&grid), bits_first(&brute), "{what} {mode} first");
        let grid = query.all_contacts(scene, options);
        let brute = brute_force::all_contacts(scene, options);
        assert_eq!(bits_events(&grid), bits_events(&brute), "{what} {mode} all");
    }
}

fn sphere(c: [f64; 3], v: [f64; 3], r: f64) -> Sphere {
    let f = |x: [f64; 3]| x.map(|x| x as f32);
    Sphere::new(f(c), f(v), r as f32, 1.0).unwrap()
}

fn gas(n: usize, phi: f64, radii: (f64, f64), seed: u64) -> SphereStore {
    let mut rng = Rng::new(seed);
    let mean_r3 = (radii.0 * radii.0 * radii.0 + radii.1 * radii.1 * radii.1) / 2.0;
    let side = (n as f64 * 4.0 / 3.0 * std::f64::consts::PI * mean_r3 / phi).cbrt();
    (0..n)
        .map(|_| {
            let c = rng.cube(side / 2.0);
            let r = radii.0 * (radii.1 / radii.0).powf(rng.unit());
            sphere(c.to_array(), rng.cube(1.0).to_array(), r)
        })
        .collect()
}

fn with_statics(spheres: SphereStore, side: f32) -> Scene {
    Scene {
        spheres,
        // Several of a kind: the statics stage then culls shapes a lane group cannot reach.
        statics: [
            Plane::new([0.0, 0.0, -side], [0.0, 0.0, 1.0])
                .unwrap()
                .into(),
            Plane::new([side, 0.0, 0.0], [-1.0, 0.2, 0.0])
                .unwrap()
                .into(),
            Cylinder::from_axis([0.0; 3], [0.0, 0.0, 1.0], side / 10.0)
                .unwrap()
                .into(),
            Cylinder::from_axis([side / 2.0, 0.0, 0.0], [0.0, 0.3, 1.0], side / 20.0)
                .unwrap()
                .into(),
            Cylinder::from_axis([-side / 2.0, side / 3.0, 0.0], [1.0, 0.0, 0.2], 1.0)
                .unwrap()
                .into(),
            Container::new([0.0; 3], 1.5 * side).unwrap().into(),
            Container::new([1.0, 0.0, 0.0], 1.2 * side).unwrap().into(),
        ]
        .into_iter()
        .collect(),
    }
}

#[test]
fn random_gases_match_brute_force() {
    for (k, &(n, phi)) in [(300, 0.05), (800, 0.3), (1500, 0.3)].iter().enumerate() {
        for radii in [(1.0, 1.0), (0.01, 10.0)] {
            // From no time at all to no limit: the last runs the successive windows.
            for t_max in [0.0, 0.5, 10.0, 1e4, f32::INFINITY] {
                let spheres = gas(n, phi, radii, 10 + k as u64);
                let scene = with_statics(spheres.clone(), 20.0);
                check(
                    &scene,
                    t_max,
                    &format!("gas n={n} phi={phi} radii={radii:?} t={t_max}"),
                );
                let bare = Scene {
                    spheres,
                    ..Scene::default()
                };
                check(&bare, t_max, "bare gas");
            }
        }
    }
}

#[test]
fn adversarial_scenes_match_brute_force() {
    let mut rng = Rng::new(3);
    let mut scenes: Vec<(&str, SphereStore, f32)> = vec![
        ("empty", SphereStore::new(), 1.0),
        (
            "one sphere",
            [sphere([0.0; 3], [1.0, 0.0, 0.0], 1.0)].as_slice().into(),
            1.0,
        ),
    ];
    // Every sphere in one cell: 200 spheres at almost the same place.
    scenes.push((
        "one cell",
        (0..200)
            .map(|_| sphere(rng.cube(0.01).to_array(), rng.cube(1.0).to_array(), 1.0))
            .collect(),
        1.0,
    ));
    // One giant among small ones.
    let mut giant: Vec<Sphere> = (0..400)
        .map(|_| sphere(rng.cube(50.0).to_array(), rng.cube(1.0).to_array(), 0.5))
        .collect();
    giant.push(sphere([0.0; 3], [0.1, 0.0, 0.0], 30.0));
    scenes.push(("giant", SphereStore::from_spheres(&giant), 2.0));
    // Spheres in a line, far apart and close together.
    scenes.push((
        "line",
        (0..500)
            .map(|i| {
                sphere(
                    [i as f64 * 3.0, 0.0, 0.0],
                    [rng.range(-1.0, 1.0), 0.0, 0.0],
                    1.0,
                )
            })
            .collect(),
        2.0,
    ));
    scenes.push((
        "long line",
        (0..300)
            .map(|i| sphere([i as f64 * 1e4, 1.0, 0.0], [0.0, 0.0, 1.0], 1.0))
            .collect(),
        5.0,
    ));
    // At rest: only overlapping pairs could touch, and at rest they never do.
    scenes.push((
        "at rest",
        (0..300)
            .map(|_| sphere(rng.cube(10.0).to_array(), [0.0; 3], 1.0))
            .collect(),
        3.0,
    ));
    // Radii over three orders of magnitude, and one very fast sphere.
    let mut fast: Vec<Sphere> = (0..300)
        .map(|_| {
            sphere(
                rng.cube(20.0).to_array(),
                rng.cube(1.0).to_array(),
                rng.range(0.01, 10.0),
            )
        })
        .collect();
    fast.push(sphere([-30.0, 0.0, 0.0], [1000.0, 3.0, 0.0], 0.1));
    scenes.push((
        "radii and a fast one",
        SphereStore::from_spheres(&fast),
        1.0,
    ));
    // Clustered: dense clumps in empty space.
    scenes.push((
        "clustered",
        (0..600)
            .map(|i| {
                let centre = [(i % 6) as f64 * 100.0, 0.0, 0.0];
                let c = rng.cube(4.0) + glam::DVec3::from(centre);
                sphere(c.to_array(), rng.cube(1.0).to_array(), 0.7)
            })
            .collect(),
        2.0,
    ));
    for (what, spheres, t_max) in scenes {
        for t in [t_max, 0.0, f32::INFINITY] {
            let scene = with_statics(spheres.clone(), 40.0);
            check(&scene, t, &format!("{what} t_max={t}"));
        }
    }
}

#[test]
fn the_query_is_the_same_for_any_thread_count() {
    // Above the grid's and the batch driver's parallel thresholds.
    let busy = with_statics(gas(40_000, 0.3, (1.0, 1.0), 5), 30.0);
    // An infinite window: successive windows, then rows for the spheres still open.
    // (No shapes: a container would catch every sphere.)
    let open = Scene {
        spheres: gas(4000, 0.02, (0.5, 2.0), 6),
        ..Scene::default()
    };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut query = SceneQuery::new();
            let options = QueryOptions::new(0.5, Accuracy::Stable).unwrap();
            let first = query.first_contacts(&busy, options);
            let all = query.all_contacts(&busy, options);
            let mut compact = Vec::new();
            query.first_contacts_compact_into(&busy, options, &mut compact);
            let unbounded = QueryOptions::new(f32::INFINITY, Accuracy::Stable).unwrap();
            let far = query.first_contacts(&open, unbounded);
            let compact: Vec<u64> = compact.iter().map(|c| c.to_bits()).collect();
            (
                bits_first(&first),
                bits_events(&all),
                compact,
                bits_first(&far),
            )
        })
    };
    let one = run(1);
    assert!(one.1.len() > 1000, "a busy scene: {} contacts", one.1.len());
    let never = one.3.iter().filter(|c| c.is_none()).count();
    assert!(never > 0 && never < 4000, "{never} of 4000 never touch");
    for threads in [2, 7] {
        assert!(one == run(threads), "{threads} threads differ from one");
    }
    let unbounded = QueryOptions::new(f32::INFINITY, Accuracy::Stable).unwrap();
    let brute = brute_force::first_contacts(&open, unbounded);
    assert_eq!(
        one.3,
        bits_first(&brute),
        "an infinite window against the brute force"
    );
}

#[test]
fn the_compact_answer_is_the_full_one() {
    let scene = with_statics(gas(3000, 0.3, (0.2, 2.0), 8), 20.0);
    let mut query = SceneQuery::new();
    for t_max in [0.0, 0.5, 3.0, f32::INFINITY] {
        let options = QueryOptions::new(t_max, Accuracy::Stable).unwrap();
        let mut compact = Vec::new();
        query.first_contacts_compact_into(&scene, options, &mut compact);
        let full = query.first_contacts(&scene, options.with_geometry(true));
        let mut geometry = Vec::new();
        spheresweep::query::geometry_of(&scene, &compact, &mut geometry);
        for (i, ((c, f), g)) in compact.iter().zip(&full).zip(&geometry).enumerate() {
            assert_eq!(c.get(), f.map(|f| (f.time, f.body)), "t {t_max} sphere {i}");
            assert_eq!(*g, f.and_then(|f| f.geometry), "t {t_max} sphere {i}");
        }
    }
}

#[test]
fn a_query_reused_on_a_moved_scene_matches_a_fresh_one() {
    // Many frames: the grid re-sorts from the last frame's cell order, the answers must not
    // depend on it. Spheres leave their cells, some cross several, the count stays.
    let mut spheres = gas(3000, 0.3, (1.0, 1.0), 9);
    let mut query = SceneQuery::new();
    let options = QueryOptions::new(0.5, Accuracy::Stable).unwrap();
    for step in 0..12 {
        let scene = with_statics(spheres.clone(), 20.0);
        let reused = query.first_contacts(&scene, options);
        let fresh = SceneQuery::new().first_contacts(&scene, options);
        assert_eq!(bits_first(&reused), bits_first(&fresh), "step {step}");
        if step % 4 == 3 {
            let brute = brute_force::first_contacts(&scene, options);
            assert_eq!(bits_first(&reused), bits_first(&brute), "step {step}");
        }
        // Move every sphere a little, and every tenth frame a few of them far.
        let dt = if step % 10 == 9 { 5.0 } else { 0.1 };
        for i in 0..spheres.len() {
            let s = spheres.get(i).unwrap();
            spheres.set_centre(i, s.centre_at(dt).to_array()).unwrap();
        }
    }
}

#[test]
fn the_grid_culls_a_dilute_gas() {
    let scene = Scene {
        spheres: gas(5000, 0.05, (1.0, 1.0), 4),
        ..Scene::default()
    };
    let mut query = SceneQuery::new();
    query.first_contacts(&scene, QueryOptions::new(0.5, Accuracy::Stable).unwrap());
    let stats = query.stats();
    assert!(stats.grid);
    // A few candidates per sphere, not n²/2.
    assert!(stats.candidate_pairs < 5 * stats.spheres, "{stats:?}");
}

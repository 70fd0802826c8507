//! Batch entry points: every length from 0 to 17 and large parallel batches give, bit for bit,
//! what the kernel gives one item at a time; padding lanes never report a hit; results do not
//! depend on the thread count; bad arguments are errors, not panics.

use proptest::prelude::*;
use spheresweep::batch::{
    earliest_sphere_contact, earliest_static_contacts, one_against_times, pair_times, static_times,
    zip_times,
};
use spheresweep::store::Field;
use spheresweep::{
    Accuracy, BatchError, Container, Cylinder, Plane, QueryOptions, Shape, Sphere, SphereStore,
    time_of_impact,
};

fn sphere() -> impl Strategy<Value = Sphere> {
    (
        [-50.0f32..50.0, -50.0f32..50.0, -50.0f32..50.0],
        [-5.0f32..5.0, -5.0f32..5.0, -5.0f32..5.0],
        0.1f32..3.0,
    )
        .prop_map(|(c, v, r)| Sphere::new(c, v, r, 1.0).unwrap())
}

fn query(mode: Accuracy) -> QueryOptions {
    QueryOptions::new(50.0, mode).unwrap()
}

/// One pair alone through the batch API: the reference point for every batch layout.
fn alone(a: &Sphere, b: &Sphere, mode: Accuracy) -> f32 {
    let mut out = [0.0];
    let (sa, sb) = (
        SphereStore::from_spheres(&[*a]),
        SphereStore::from_spheres(&[*b]),
    );
    zip_times(&sa, &sb, query(mode), &mut out).unwrap();
    out[0]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    #[test]
    fn every_layout_gives_the_same_bits(
        a in prop::collection::vec(sphere(), 0..=17),
        b in prop::collection::vec(sphere(), 17),
    ) {
        let n = a.len();
        let b = &b[..n];
        let (sa, sb) = (SphereStore::from_spheres(&a), SphereStore::from_spheres(b));
        let mut both = SphereStore::from_spheres(&a);
        b.iter().for_each(|s| both.push(s));
        let pairs: Vec<[u32; 2]> = (0..n as u32).map(|i| [i, i + n as u32]).collect();
        for mode in Accuracy::ALL {
            let expected: Vec<f32> = (0..n).map(|i| alone(&a[i], &b[i], mode)).collect();
            let mut zipped = vec![0.0; n];
            zip_times(&sa, &sb, query(mode), &mut zipped).unwrap();
            let mut listed = vec![0.0; n];
            pair_times(&both, &pairs, query(mode), &mut listed).unwrap();
            prop_assert_eq!(to_bits(&zipped), to_bits(&expected));
            // The single-pair entry point gives the batch's bits.
            let single: Vec<f32> = (0..n)
                .map(|i| time_of_impact(&a[i], &Shape::Sphere(b[i]), query(mode)).unwrap_or(f32::INFINITY))
                .collect();
            prop_assert_eq!(to_bits(&single), to_bits(&expected));
            prop_assert_eq!(to_bits(&listed), to_bits(&expected));
            if let Some(first) = a.first() {
                let mut one = vec![0.0; n];
                one_against_times(first, &sb, query(mode), &mut one).unwrap();
                let one_expected: Vec<f32> = b.iter().map(|s| alone(first, s, mode)).collect();
                prop_assert_eq!(to_bits(&one), to_bits(&one_expected));
                let best = earliest_sphere_contact(first, &sb, query(mode));
                let min = one_expected.iter().cloned().fold(f32::INFINITY, f32::min);
                prop_assert_eq!(best.map(|f| f.time), min.is_finite().then_some(min));
                if let Some(f) = best {
                    // Ties go to the lowest index.
                    prop_assert_eq!(f.body.index as usize, one_expected.iter().position(|&t| t == min).unwrap());
                }
            }
        }
    }

    #[test]
    fn static_shapes_report_the_earliest_and_lowest_index(
        spheres in prop::collection::vec(sphere(), 0..=17),
        normals in prop::collection::vec([-1.0f32..1.0, -1.0f32..1.0, 0.1f32..1.0], 1..4),
    ) {
        let store = SphereStore::from_spheres(&spheres);
        let planes: Vec<Plane> = normals.iter().enumerate()
            .map(|(k, n)| Plane::new([0.0, 0.0, -10.0 * k as f32], *n).unwrap())
            .collect();
        for mode in Accuracy::ALL {
            let got = earliest_static_contacts(&store, &planes, query(mode));
            prop_assert_eq!(got.len(), spheres.len());
            for (i, s) in spheres.iter().enumerate() {
                let each: Vec<Option<f32>> = planes.iter()
                    .map(|p| earliest_static_contacts(&SphereStore::from_spheres(&[*s]), &[*p], query(mode))[0].map(|f| f.time))
                    .collect();
                let best = each.iter().flatten().cloned().fold(f32::INFINITY, f32::min);
                // static_times gives the same bits for one shape as earliest_static_contacts.
                let mut one = vec![0.0; spheres.len()];
                static_times(&store, &planes[0], query(mode), &mut one).unwrap();
                prop_assert_eq!(one[i].is_finite().then_some(one[i]), each[0]);
                prop_assert_eq!(time_of_impact(s, &Shape::Plane(planes[0]), query(mode)), each[0]);
                match got[i] {
                    None => prop_assert!(best.is_infinite()),
                    Some(f) => {
                        prop_assert_eq!(f.time, best);
                        prop_assert_eq!(f.body.index as usize, each.iter().position(|t| *t == Some(best)).unwrap());
                    }
                }
            }
        }
    }
}

fn to_bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|t| t.to_bits()).collect()
}

#[test]
fn padding_lanes_are_nan_and_never_hit() {
    // A zeroed padding lane would be a point sphere at rest at the origin: the query sphere
    // below flies straight through the origin and would hit it.
    let through_origin = Sphere::new([-10.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1.0, 1.0).unwrap();
    let far = Sphere::new([0.0, 100.0, 0.0], [0.0; 3], 1.0, 1.0).unwrap();
    for n in 1..=17 {
        let block = SphereStore::from_spheres(&vec![far; n]);
        assert_eq!(block.padded_len() % 8, 0);
        let lanes = *block.blocks().last().unwrap().column(Field::R).unwrap();
        let pads = block.padded_len() - n;
        assert!(
            lanes[8 - pads..].iter().all(|x| x.is_nan()),
            "pads of {n}: {lanes:?}"
        );
        for mode in Accuracy::ALL {
            assert_eq!(
                earliest_sphere_contact(&through_origin, &block, query(mode)),
                None
            );
            let containers = [Container::new([0.0; 3], 1000.0).unwrap()];
            let hits = earliest_static_contacts(&block, &containers, query(mode));
            assert_eq!(hits.len(), n);
        }
    }
}

#[test]
fn large_batches_are_identical_for_any_thread_count() {
    let n = 100_003; // above the parallel threshold, not a multiple of 8
    let spheres: Vec<Sphere> = (0..n)
        .map(|i| {
            let f = i as f32;
            let c = [
                (f * 0.37).sin() * 40.0,
                (f * 0.11).cos() * 40.0,
                (f * 0.07).sin() * 40.0,
            ];
            let v = [
                (f * 0.5).cos() * 3.0,
                (f * 0.3).sin() * 3.0,
                (f * 0.9).cos() * 3.0,
            ];
            Sphere::new(c, v, 0.5 + (i % 7) as f32 * 0.1, 1.0).unwrap()
        })
        .collect();
    let a = SphereStore::from_spheres(&spheres[..n / 2]);
    let b = SphereStore::from_spheres(&spheres[n / 2..n / 2 * 2]);
    let planes = [Plane::new([0.0, 0.0, -30.0], [0.1, 0.2, 1.0]).unwrap()];
    let cylinders = [Cylinder::new([0.0; 3], [0.0, 1.0, 1.0], 2.0).unwrap()];
    let all = SphereStore::from_spheres(&spheres);
    let run = |threads: usize, mode: Accuracy| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut out = vec![0.0; a.len()];
            zip_times(&a, &b, query(mode), &mut out).unwrap();
            let p = earliest_static_contacts(&all, &planes, query(mode));
            let c = earliest_static_contacts(&all, &cylinders, query(mode));
            (to_bits(&out), p, c)
        })
    };
    for mode in Accuracy::ALL {
        let one = run(1, mode);
        assert!(
            one.0.iter().any(|&t| f32::from_bits(t).is_finite()),
            "some hits"
        );
        assert_eq!(one, run(2, mode), "{mode}");
        // And the parallel result matches item-by-item evaluation at a few places.
        for i in [0, 7, 8, 4095, 4096, 40_000, a.len() - 1] {
            let expected = alone(&a.get(i).unwrap(), &b.get(i).unwrap(), mode);
            assert_eq!(one.0[i], expected.to_bits(), "{mode} item {i}");
        }
    }
}

#[test]
fn geometry_is_computed_for_hits_only() {
    let floor = [Plane::new([0.0; 3], [0.0, 0.0, 1.0]).unwrap()];
    let store = SphereStore::from_spheres(&[
        Sphere::new([0.0, 0.0, 3.0], [0.0, 0.0, -1.0], 1.0, 1.0).unwrap(),
        Sphere::new([0.0, 0.0, 3.0], [1.0, 0.0, 0.0], 1.0, 1.0).unwrap(),
    ]);
    let got = earliest_static_contacts(&store, &floor, query(Accuracy::Stable).with_geometry(true));
    let first = got[0].unwrap();
    let contact = first.geometry.unwrap();
    assert_eq!(
        (first.time, contact.point.z, contact.normal.z),
        (2.0, 0.0, 1.0)
    );
    assert!(got[1].is_none());
    // Without asking, no geometry.
    let plain = earliest_static_contacts(&store, &floor, query(Accuracy::Stable));
    assert_eq!(plain[0].unwrap().geometry, None);
}

#[test]
fn bad_arguments_are_errors() {
    let s = Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0).unwrap();
    let two = SphereStore::from_spheres(&[s, s]);
    let one = SphereStore::from_spheres(&[s]);
    let q = query(Accuracy::Stable);
    assert!(
        matches!(QueryOptions::new(f32::NAN, Accuracy::Stable), Err(BatchError::Window(t)) if t.is_nan())
    );
    assert!(matches!(
        QueryOptions::new(-1.0, Accuracy::Stable),
        Err(BatchError::Window(_))
    ));
    assert!(QueryOptions::new(f32::INFINITY, Accuracy::Stable).is_ok());
    let mut out = [0.0; 2];
    assert_eq!(
        zip_times(&two, &one, q, &mut out),
        Err(BatchError::StoreLengths { a: 2, b: 1 })
    );
    assert_eq!(
        zip_times(&two, &two, q, &mut out[..1]),
        Err(BatchError::OutputLength {
            expected: 2,
            found: 1
        })
    );
    assert_eq!(
        pair_times(&two, &[[0, 1], [1, 2]], q, &mut out),
        Err(BatchError::IndexOutOfRange {
            pair: 1,
            index: 2,
            len: 2
        })
    );
    let e = pair_times(&two, &[[0, 9]], q, &mut out[..1]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "pair 0: sphere index 9 is out of range (the store holds 2)"
    );
}

#[test]
fn scene_query_matches_the_reference_on_the_demo() {
    use spheresweep::{query, reference};
    let scene = spheresweep::scene::demo();
    let expected = reference::scene::first_contacts_brute_force(&scene, 10.0);
    for mode in Accuracy::ALL {
        let options = QueryOptions::new(10.0, mode).unwrap().with_geometry(true);
        let got = query::first_contacts(&scene, options);
        for (g, e) in got.iter().zip(&expected) {
            match (g, e) {
                (None, None) => {}
                (Some(g), Some((body, c))) => {
                    assert_eq!(g.body, *body, "{mode}");
                    // Demo times are O(1): within a few f32 ulps of the f64 reference.
                    assert!(
                        (f64::from(g.time) - c.time).abs()
                            <= 8.0 * f64::from(f32::EPSILON) * c.time.max(1.0),
                        "{mode}: {} vs {}",
                        g.time,
                        c.time
                    );
                }
                _ => panic!("{mode}: {g:?} vs {e:?}"),
            }
        }
    }
}

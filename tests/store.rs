//! The store's way in and out: columns in, column views out, masses kept, in-place updates
//! validated, and errors that name the sphere and the field.

use spheresweep::store::{Columns, Field};
use spheresweep::{Error, Problem, ShapeKind, Sphere, SphereStore, StoreError};

fn columns<'a>(c: &'a [Vec<f32>; 8], mass: bool) -> Columns<'a> {
    Columns {
        x: &c[0],
        y: &c[1],
        z: &c[2],
        vx: &c[3],
        vy: &c[4],
        vz: &c[5],
        r: &c[6],
        m: mass.then_some(&c[7][..]),
    }
}

fn data(n: usize) -> [Vec<f32>; 8] {
    std::array::from_fn(|f| (0..n).map(|i| (f * 100 + i) as f32 + 0.5).collect())
}

#[test]
fn columns_round_trip_through_the_store_for_every_length() {
    for n in 0..=17 {
        let c = data(n);
        let store = SphereStore::from_columns(&columns(&c, true)).unwrap();
        assert_eq!(store.len(), n);
        for (f, field) in Field::ALL.into_iter().enumerate() {
            let col = store.column(field);
            assert_eq!(col.field(), field);
            assert_eq!(col.to_vec(), c[f], "{field}");
            let mut out = vec![0.0; n];
            col.copy_to(&mut out).unwrap();
            assert_eq!(out, c[f]);
            assert_eq!(col.get(n), None);
        }
        // The same spheres as built one by one.
        let spheres: Vec<Sphere> = (0..n)
            .map(|i| {
                Sphere::new(
                    [c[0][i], c[1][i], c[2][i]],
                    [c[3][i], c[4][i], c[5][i]],
                    c[6][i],
                    c[7][i],
                )
                .unwrap()
            })
            .collect();
        assert_eq!(store, SphereStore::from_spheres(&spheres));
        assert_eq!(store.iter().collect::<Vec<_>>(), spheres);
    }
}

#[test]
fn without_a_mass_column_every_mass_is_one() {
    let c = data(3);
    let store = SphereStore::from_columns(&columns(&c, false)).unwrap();
    assert_eq!(store.masses(), [1.0; 3]);
}

#[test]
fn column_errors_name_the_column_or_the_sphere_and_field() {
    let mut c = data(4);
    c[4].pop();
    assert_eq!(
        SphereStore::from_columns(&columns(&c, true)).unwrap_err(),
        StoreError::LengthMismatch {
            field: Field::Vy,
            expected: 4,
            found: 3
        }
    );
    let mut c = data(4);
    c[7][2] = 0.0;
    let err = SphereStore::from_columns(&columns(&c, true)).unwrap_err();
    assert_eq!(err.to_string(), "sphere 2: mass must be greater than zero");
    let mut c = data(4);
    c[1][3] = f32::NAN;
    match SphereStore::from_columns(&columns(&c, true)).unwrap_err() {
        StoreError::Invalid { index: 3, source } => {
            assert_eq!(
                (source.kind, source.field, source.problem),
                (ShapeKind::Sphere, "centre", Problem::NotFinite)
            );
        }
        e => panic!("{e}"),
    }
    // One error type across areas.
    let e: Error = SphereStore::from_columns(&columns(&c, true))
        .unwrap_err()
        .into();
    assert!(e.to_string().starts_with("sphere 3: "));
}

#[test]
fn in_place_updates_are_validated() {
    let c = data(9);
    let mut store = SphereStore::from_columns(&columns(&c, true)).unwrap();
    store.set_centre(8, [1.0, 2.0, 3.0]).unwrap();
    store.set_velocity(0, [-1.0, 0.0, 4.0]).unwrap();
    let s8 = store.get(8).unwrap();
    assert_eq!(s8.centre().to_array(), [1.0, 2.0, 3.0]);
    assert_eq!(s8.mass(), c[7][8]);
    assert_eq!(
        store.get(0).unwrap().velocity().to_array(),
        [-1.0, 0.0, 4.0]
    );
    assert_eq!(
        store.set_centre(9, [0.0; 3]),
        Err(StoreError::IndexOutOfRange { index: 9, len: 9 })
    );
    let before = store.clone();
    let err = store
        .set_velocity(4, [0.0, f32::INFINITY, 0.0])
        .unwrap_err();
    assert_eq!(err.to_string(), "sphere 4: velocity is NaN or infinite");
    assert_eq!(store, before, "a refused update changes nothing");
    let mut out = [0.0; 2];
    assert!(store.column(Field::X).copy_to(&mut out).is_err());
}

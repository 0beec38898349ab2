//! Tables that once passed validation and then broke the physics (an allocation without
//! bound, a NaN ball or corner wall, millions of bodies): each is refused with an error that names the
//! field, the value and the range. Every file in `tests/bad_tables/` is one of them.

use std::path::PathBuf;

use space_foosball::table::{Table, TableError};

/// Each file of `tests/bad_tables/` and the message it must give.
const EXPECTED: &[(&str, &str)] = &[
    (
        "goal-height-1e19",
        "goal.height_m must be within 0.01 … 1, got 1e19",
    ),
    (
        "ball-mass-1e308",
        "ball.mass_kg must be within 0.001 … 1, got 1e308",
    ),
    (
        "ball-mass-1e-308",
        "ball.mass_kg must be within 0.001 … 1, got 1e-308",
    ),
    (
        "ball-diameter-1e19",
        "ball.diameter_m must be within 0.005 … 0.2, got 1e19",
    ),
    (
        "field-700-km-wide",
        "field.width_m must be within 0.2 … 3, got 7e5",
    ),
    (
        "field-length-negative",
        "field.length_m must be within 0.3 … 5, got -1.2",
    ),
    ("million-men-on-a-rod", "rod 0: 1000000 men, must be 1 … 11"),
    (
        "corner-ramp-5e-324",
        "field.corner_ramp_m (0 for no ramp) must be within 0.001 … 0.35, got 5e-324",
    ),
    (
        "million-men-on-a-700-km-table",
        "field.width_m must be within 0.2 … 3, got 7e5",
    ),
];

fn dir() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/bad_tables"))
}

#[test]
fn every_bad_table_file_is_refused_by_name() {
    let mut files: Vec<String> = std::fs::read_dir(dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    files.sort();
    let mut named: Vec<String> = EXPECTED.iter().map(|(f, _)| f.to_string()).collect();
    named.sort();
    assert_eq!(
        files, named,
        "every file in bad_tables/ has its expected message"
    );
    for (file, message) in EXPECTED {
        let e = Table::load(&dir().join(format!("{file}.toml"))).unwrap_err();
        assert_eq!(&e.to_string(), message, "{file}");
    }
}

fn rejected(edit: impl FnOnce(&mut Table)) -> TableError {
    let mut t = Table::standard();
    edit(&mut t);
    t.validate().unwrap_err()
}

#[test]
fn the_reproducers_are_typed_errors() {
    let e = rejected(|t| t.goal.height_m = 1e19);
    assert!(
        matches!(&e, TableError::OutOfRange { what, .. } if what == "goal.height_m"),
        "{e}"
    );
    for mass in [1e308, 1e-308, 0.0, f64::NAN] {
        let e = rejected(|t| t.ball.mass_kg = mass);
        assert!(
            matches!(&e, TableError::OutOfRange { what, .. } if what == "ball.mass_kg"),
            "{mass}: {e}"
        );
    }
    // 700 km wide with 10⁶ men on the midfield rod, spaced so that they fit: the width is
    // refused, and with a real width the men are.
    let e = rejected(|t| {
        t.field.width_m = 7e5;
        t.rods[3].men = 1_000_000;
        t.rods[3].spacing_m = 0.5;
    });
    assert!(
        matches!(&e, TableError::OutOfRange { what, .. } if what == "field.width_m"),
        "{e}"
    );
    let e = rejected(|t| t.rods[3].men = 1_000_000);
    assert_eq!(
        e,
        TableError::Men {
            rod: 3,
            men: 1_000_000,
            lo: 1,
            hi: 11
        }
    );
}

#[test]
fn character_parameters_are_ranged_too() {
    let e = rejected(|t| {
        let mut p = t.teams[1].character_params();
        p.mass_kg = 1e300;
        t.teams[1].params = Some(p);
    });
    assert_eq!(
        e.to_string(),
        "Away params.mass_kg must be within 0.005 … 2, got 1e300"
    );
    let e = rejected(|t| {
        let mut p = t.teams[0].character_params();
        p.foot_reach_m = 1e19;
        t.teams[0].params = Some(p);
    });
    assert!(e.to_string().starts_with("Home params.foot_reach_m"), "{e}");
}

#[test]
fn more_rods_than_board_ports_are_refused() {
    let e = rejected(|t| {
        let extra = t.rods[7].clone();
        t.rods.push(extra);
    });
    assert!(e.to_string().contains("9 rods: at most 8"), "{e}");
}

#[test]
fn the_presets_lie_inside_every_range() {
    Table::standard().validate().unwrap();
    for file in ["standard", "paper"] {
        let path = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tables"))
            .join(format!("{file}.toml"));
        Table::load(&path).unwrap();
    }
}

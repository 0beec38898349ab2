//! The table as data: presets, file format, validation.

use space_foosball::table::{CharacterType, Role, Table, TableError};
use space_foosball::Side;

#[test]
fn standard_preset_is_1_2_3_5_5_3_2_1_alternating_as_on_a_real_table() {
    let t = Table::standard();
    let men: Vec<usize> = t.rods.iter().map(|r| r.men).collect();
    assert_eq!(men, [1, 2, 3, 5, 5, 3, 2, 1]);
    use Role::*;
    use Side::*;
    let order: Vec<(Side, Role)> = t.rods.iter().map(|r| (r.team, r.role)).collect();
    assert_eq!(
        order,
        [
            (Home, Goalkeeper),
            (Home, Defence),
            (Away, Attack),
            (Home, Midfield),
            (Away, Midfield),
            (Home, Attack),
            (Away, Defence),
            (Away, Goalkeeper),
        ]
    );
    // 150 mm apart, symmetric about the centre line.
    for w in t.rods.windows(2) {
        assert!((w[1].x_m - w[0].x_m - 0.150).abs() < 1e-9);
    }
    assert!((t.rods[0].x_m + t.rods[7].x_m).abs() < 1e-12);
    // Spacing and travel per role.
    for r in &t.rods {
        let (spacing, travel) = match r.role {
            Goalkeeper => (0.0, 0.190),
            Defence => (0.238, 0.356),
            Midfield => (0.118, 0.116),
            Attack => (0.208, 0.180),
        };
        assert_eq!((r.spacing_m, r.travel_m), (spacing, travel));
    }
    assert_eq!((t.field.length_m, t.field.width_m), (1.2, 0.7));
    assert_eq!((t.ball.diameter_m, t.ball.mass_kg), (0.035, 0.027));
    let ports: Vec<usize> = t.rods.iter().map(|r| r.port).collect();
    assert_eq!(ports, [0, 1, 2, 3, 4, 5, 6, 7]);
}

#[test]
fn paper_preset_has_four_characters_on_every_rod_and_both_types() {
    let t = Table::paper();
    assert_eq!(t.rods.len(), 8);
    assert!(t.rods.iter().all(|r| r.men == 4));
    assert_eq!(t.team(Side::Home).character, CharacterType::TallThin);
    assert_eq!(t.team(Side::Away).character, CharacterType::ShortWide);
    assert_eq!(t.rods_of(Side::Home).count(), 4);
    assert_eq!(Table::preset("paper").unwrap(), t);
    assert!(Table::preset("nope").is_err());
}

#[test]
fn toml_round_trips() {
    for t in [Table::standard(), Table::paper()] {
        let text = t.to_toml();
        assert_eq!(Table::from_toml(&text).unwrap(), t);
    }
}

#[test]
fn team_can_override_character_parameters() {
    let mut t = Table::standard();
    let mut p = CharacterType::ShortWide.params();
    p.mass_kg = 0.1;
    t.teams[1].params = Some(p);
    let back = Table::from_toml(&t.to_toml()).unwrap();
    assert_eq!(back.character_of(7).mass_kg, 0.1);
    assert_eq!(back.character_of(0), CharacterType::TallThin.params());
}

fn rejected(edit: impl FnOnce(&mut Table)) -> TableError {
    let mut t = Table::standard();
    edit(&mut t);
    let err = t.validate().unwrap_err();
    // The same error through the file format.
    assert_eq!(Table::from_toml(&t.to_toml()).unwrap_err(), err);
    err
}

#[test]
fn men_that_do_not_fit_the_width_are_rejected() {
    let err = rejected(|t| t.rods[3].travel_m = 0.25);
    assert!(
        matches!(err, TableError::MenDoNotFit { rod: 3, men: 5, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("rod 3"));
    let err = rejected(|t| {
        t.field.width_m = 0.5;
        // Ramps that still fit beside the goal of the narrower end wall.
        t.field.corner_ramp_m = 0.1;
    });
    assert!(matches!(err, TableError::MenDoNotFit { .. }), "{err}");
}

#[test]
fn negative_and_non_finite_sizes_are_rejected_by_name() {
    let err = rejected(|t| t.field.length_m = -1.2);
    assert!(err.to_string().contains("field.length_m"), "{err}");
    let err = rejected(|t| t.ball.diameter_m = 0.0);
    assert!(err.to_string().contains("ball.diameter_m"), "{err}");
    let err = rejected(|t| t.rods[2].travel_m = -0.1);
    assert!(err.to_string().contains("rod 2 travel_m"), "{err}");
    let err = rejected(|t| t.ball.restitution = 1.5);
    assert!(err.to_string().contains("ball.restitution"), "{err}");
    // NaN does not survive TOML; checked directly.
    let mut t = Table::standard();
    t.goal.width_m = f64::NAN;
    assert!(t
        .validate()
        .unwrap_err()
        .to_string()
        .contains("goal.width_m"));
}

#[test]
fn inconsistent_layouts_are_rejected() {
    let err = rejected(|t| t.rods[4].port = 3);
    assert!(
        matches!(
            err,
            TableError::Port {
                rod: 4,
                port: 3,
                ..
            }
        ),
        "{err}"
    );
    let err = rejected(|t| t.rods[4].port = 8);
    assert!(matches!(err, TableError::Port { rod: 4, .. }), "{err}");
    let err = rejected(|t| t.rods.swap(1, 2));
    assert!(
        matches!(err, TableError::RodPlacement { rod: 2, .. }),
        "{err}"
    );
    let err = rejected(|t| t.rods[7].x_m = 0.61);
    assert!(
        matches!(err, TableError::RodPlacement { rod: 7, .. }),
        "{err}"
    );
    let err = rejected(|t| t.rods[3].spacing_m = 0.015);
    assert!(
        matches!(err, TableError::MenOverlap { rod: 3, .. }),
        "{err}"
    );
    let err = rejected(|t| t.teams.swap(0, 1));
    assert!(matches!(err, TableError::Inconsistent(_)), "{err}");
    let err = rejected(|t| t.goal.height_m = 0.03);
    assert!(matches!(err, TableError::Inconsistent(_)), "{err}");
    let err = rejected(|t| t.field.rod_height_m = 0.2);
    assert!(
        matches!(
            err,
            TableError::Reach {
                side: Side::Home,
                ..
            }
        ),
        "{err}"
    );
    let err = rejected(|t| t.field.rod_height_m = 0.09);
    assert!(matches!(err, TableError::Reach { .. }), "{err}");
    let err = rejected(|t| t.rods.retain(|r| r.team == Side::Home));
    assert!(err.to_string().contains("Away has no rods"), "{err}");
}

#[test]
fn unknown_fields_and_bad_syntax_are_parse_errors() {
    let text = Table::standard()
        .to_toml()
        .replace("[field]", "[field]\ncolour = 3");
    let err = Table::from_toml(&text).unwrap_err();
    assert!(matches!(err, TableError::Parse(_)), "{err}");
    assert!(err.to_string().contains("colour"), "{err}");
    assert!(matches!(
        Table::from_toml("name = ").unwrap_err(),
        TableError::Parse(_)
    ));
    let err = Table::load(std::path::Path::new("/nonexistent/table.toml")).unwrap_err();
    assert!(matches!(err, TableError::Io { .. }));
}

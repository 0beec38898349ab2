//! A reference table for the renderer's own tests: the sizes of the game's standard
//! table (eight rods 1-2-3-5-5-3-2-1, 150 mm apart), written out as view data so the
//! renderer's tests need nothing of the game. The program fills its views from the
//! real table files instead.

use crate::view::{CharacterKind, CharacterLook, RodGeometry, TableGeometry, Team};

/// Both character looks, in [`CharacterKind::index`] order.
pub(crate) fn reference_looks() -> [CharacterLook; 2] {
    [
        CharacterLook {
            kind: CharacterKind::TallThin,
            body_width_m: 0.020,
            body_depth_m: 0.012,
            head_height_m: 0.030,
            shoulder_height_m: 0.010,
            foot_reach_m: 0.096,
            foot_width_m: 0.018,
        },
        CharacterLook {
            kind: CharacterKind::ShortWide,
            body_width_m: 0.034,
            body_depth_m: 0.020,
            head_height_m: 0.020,
            shoulder_height_m: 0.005,
            foot_reach_m: 0.088,
            foot_width_m: 0.030,
        },
    ]
}

/// The reference table with `characters` for `[home, away]`.
pub(crate) fn reference_table_with(characters: [CharacterKind; 2]) -> TableGeometry {
    use Team::{Away, Home};
    // (x, team, men, spacing, travel)
    let rods = [
        (-0.525, Home, 1, 0.0, 0.19),
        (-0.375, Home, 2, 0.238, 0.356),
        (-0.225, Away, 3, 0.208, 0.18),
        (-0.075, Home, 5, 0.118, 0.116),
        (0.075, Away, 5, 0.118, 0.116),
        (0.225, Home, 3, 0.208, 0.18),
        (0.375, Away, 2, 0.238, 0.356),
        (0.525, Away, 1, 0.0, 0.19),
    ];
    TableGeometry {
        length_m: 1.2,
        width_m: 0.7,
        wall_height_m: 0.12,
        rod_height_m: 0.1,
        goal_width_m: 0.205,
        goal_height_m: 0.075,
        goal_depth_m: 0.1,
        ball_radius_m: 0.0175,
        rods: rods
            .iter()
            .map(|&(x_m, team, men, spacing, travel_m)| RodGeometry {
                x_m,
                team,
                travel_m,
                man_offsets_m: (0..men)
                    .map(|k| (k as f64 - 0.5 * (men as f64 - 1.0)) * spacing)
                    .collect(),
            })
            .collect(),
        characters,
        looks: reference_looks(),
        team_names: ["HOME".into(), "AWAY".into()],
    }
}

/// The reference table, both teams tall-and-thin.
pub(crate) fn reference_table() -> TableGeometry {
    reference_table_with([CharacterKind::TallThin; 2])
}

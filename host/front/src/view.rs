//! The game → view conversion: the renderer's view model ([`foosball_render::view`])
//! filled in from the game's table, sides and characters. The renderer knows nothing
//! of the game; this is the one place that knows both.

use foosball_render::{
    CharacterKind, CharacterLook, FrameSnapshot, RodGeometry, TableGeometry, Team,
};
use space_foosball::side::Side;
use space_foosball::table::{CharacterType, Table};

/// The view's team of a game side.
pub fn team(side: Side) -> Team {
    match side {
        Side::Home => Team::Home,
        Side::Away => Team::Away,
    }
}

/// The view's kind of a game character type.
pub fn kind(c: CharacterType) -> CharacterKind {
    match c {
        CharacterType::TallThin => CharacterKind::TallThin,
        CharacterType::ShortWide => CharacterKind::ShortWide,
    }
}

/// How a character type is drawn: its physical sizes (man frame, m).
pub fn look(c: CharacterType) -> CharacterLook {
    let p = c.params();
    CharacterLook {
        kind: kind(c),
        body_width_m: p.body_width_m,
        body_depth_m: p.body_depth_m,
        head_height_m: p.head_height_m,
        shoulder_height_m: p.shoulder_height_m,
        foot_reach_m: p.foot_reach_m,
        foot_width_m: p.foot_width_m,
    }
}

/// The drawn geometry of `table`: field, goals, ball, rods with their men, the teams'
/// character kinds and both kinds' looks; the teams named HOME and AWAY.
pub fn table_geometry(table: &Table) -> TableGeometry {
    TableGeometry {
        length_m: table.field.length_m,
        width_m: table.field.width_m,
        wall_height_m: table.field.wall_height_m,
        rod_height_m: table.field.rod_height_m,
        goal_width_m: table.goal.width_m,
        goal_height_m: table.goal.height_m,
        goal_depth_m: table.goal.depth_m,
        ball_radius_m: table.ball.radius_m(),
        rods: table
            .rods
            .iter()
            .map(|r| RodGeometry {
                x_m: r.x_m,
                team: team(r.team),
                travel_m: r.travel_m,
                man_offsets_m: r.man_offsets(),
            })
            .collect(),
        characters: [
            kind(table.teams[0].character),
            kind(table.teams[1].character),
        ],
        looks: [
            look(CharacterType::TallThin),
            look(CharacterType::ShortWide),
        ],
        team_names: ["HOME".into(), "AWAY".into()],
    }
}

/// The table at rest (rods centred, ball on the centre spot), as drawn.
pub fn at_rest(table: &Table) -> FrameSnapshot {
    FrameSnapshot::at_rest(&table_geometry(table))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_view_follows_the_table() {
        let mut t = Table::standard();
        t.teams[1].character = CharacterType::ShortWide;
        let g = table_geometry(&t);
        assert_eq!(g.rods.len(), t.rods.len());
        for (r, v) in t.rods.iter().zip(&g.rods) {
            assert_eq!(v.man_offsets_m, r.man_offsets());
            assert_eq!(v.team, team(r.team));
        }
        assert_eq!(g.look_of(Team::Away).kind, CharacterKind::ShortWide);
        assert_eq!(
            g.look_of(Team::Home).foot_reach_m,
            t.character_of(0).foot_reach_m
        );
        for side in Side::BOTH {
            assert_eq!(g.goal_line_x(team(side)), t.goal_line_x(side));
            assert_eq!(team(side).attack_dir(), side.attack_dir());
        }
        // The men stand where the game puts them.
        let s = at_rest(&t);
        let men: usize = t.rods.iter().map(|r| r.men).sum();
        assert_eq!(s.men.len(), men);
        assert_eq!(s.men[0].pivot[1], t.rods[0].man_positions(0.0)[0]);
    }
}

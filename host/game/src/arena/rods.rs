//! A rod as an articulated tree: the bar and its men on a cylindrical joint, driven by the
//! player's hand.
//!
//! Each rod is one link on a cylindrical joint from the table to the rod (paper §5.1): the
//! joint frame sits on the rod axis at the rod's `x` and height, its axis along the table's
//! `+y`; coordinate 0 is the angle about `+y` (rad, 0 = feet down), coordinate 1 the slide
//! along `+y` (m, 0 = centred). The link carries the steel bar (a capsule: its rounded ends
//! lie in or beyond the side walls at every slide, where the ball never reaches, and the
//! engine tests a capsule against the walls' boxes in closed form) and every man's
//! shapes ([`super::parts::man_shapes`]) — several shapes on one link make it a compound
//! body; each man hangs from his shoulder on the rod axis. The link's mass and inertia are
//! the bar's and the men's, summed by [`Compound::new`].
//!
//! The player's hand is a motor on each coordinate: a PD servo towards the calibrated
//! sensor pose, `τ = k (q* − q) + c (q̇* − q̇)`, limited to the hand's force along the rod
//! and torque about it ([`super::ArenaSettings::hand_force_n`],
//! [`super::ArenaSettings::hand_torque_n_m`]). Gains put the servo's natural frequency at
//! [`super::ArenaSettings::servo_hertz`] for this rod's own mass and inertia, so a light
//! goalkeeper rod and a heavy five-man rod follow the hand alike. The slide's travel ends
//! are the drive's limits.

use super::parts::{man_shapes, z_to_y_rotation, ROD_RADIUS_M, WALL_THICKNESS_M};
use super::{ArenaError, ArenaSettings, GRAVITY_M_PER_S2};
use crate::table::Table;
use virtual_physics::algebra::Mat3;
use virtual_physics::algebra::{Inertia, Sym3, Vec3, SE3};
use virtual_physics::geometry::{Compound, Material, PartDesc, Shape};
use virtual_physics::model::{ArticulatedTree, Cylindrical};
use virtual_physics::pipeline::ArticulatedSystem;
use virtual_physics::pipeline::Motor;

/// Density of the rods' steel, kg/m³.
const STEEL_KG_PER_M3: f64 = 7850.0;
/// Wall of the hollow steel rods, m (16 mm × 1.5 mm tube: 0.54 kg per metre).
const ROD_WALL_M: f64 = 0.0015;

/// Velocity coordinate of a rod's turn (rad).
pub(crate) const SPIN: usize = 0;
/// Velocity coordinate of a rod's slide (m).
pub(crate) const SLIDE: usize = 1;

/// Half the length of rod `rod`'s bar, m: across the field and through both side walls at
/// every slide of its travel.
pub(crate) fn bar_half_length_m(table: &Table, rod: usize) -> f64 {
    0.5 * table.field.width_m + WALL_THICKNESS_M + table.rods[rod].half_travel_m()
}

/// The bar and the men of rod `rod` as parts in the link frame (joint frame on the rod
/// axis): shape, pose, mass (kg).
fn parts(table: &Table, rod: usize, man: Material) -> Vec<PartDesc> {
    let half = bar_half_length_m(table, rod);
    let inner = ROD_RADIUS_M - ROD_WALL_M;
    let bar_mass = STEEL_KG_PER_M3
        * std::f64::consts::PI
        * (ROD_RADIUS_M * ROD_RADIUS_M - inner * inner)
        * 2.0
        * half;
    let mut out = vec![PartDesc {
        shape: Shape::Capsule {
            radius: ROD_RADIUS_M,
            half_height: half - ROD_RADIUS_M,
        },
        pose: SE3::new(z_to_y_rotation(), Vec3::zeros()),
        mass: bar_mass,
        material: man,
    }];
    let character = table.character_of(rod);
    let shapes = man_shapes(&character);
    let volume: f64 = shapes.iter().map(|(s, _, _)| s.volume()).sum();
    for offset in table.rods[rod].man_offsets() {
        for (shape, centre, rot) in &shapes {
            out.push(PartDesc {
                shape: shape.clone(),
                pose: SE3::new(*rot, centre + Vec3::new(0.0, offset, 0.0)),
                mass: character.mass_kg * shape.volume() / volume,
                material: man,
            });
        }
    }
    out
}

/// Mass (kg) and inertia about the axis (kg·m²) of rod `rod`'s link: what its servo moves.
pub fn rod_mass_and_axial_inertia(table: &Table, rod: usize) -> (f64, f64) {
    let parts = parts(table, rod, Material::default());
    match Compound::new(&parts) {
        Ok((_, mass)) => {
            let inertia = link_inertia(&mass);
            let i_axis = Inertia::from_com(mass.mass, com(&mass), inertia);
            (mass.mass, i_axis.i.yy)
        }
        Err(_) => (0.0, 0.0),
    }
}

fn com(mass: &virtual_physics::geometry::CompoundMass) -> Vec3<f64> {
    mass.body_in_reference.p
}

/// The inertia about the centre of mass in the link frame: `R diag(I) Rᵀ`.
fn link_inertia(mass: &virtual_physics::geometry::CompoundMass) -> Sym3<f64> {
    let r = mass.body_in_reference.r;
    let m: Mat3 = r * Mat3::from_diagonal(&mass.principal_inertia) * r.transpose();
    Sym3::new(
        m[(0, 0)],
        m[(1, 1)],
        m[(2, 2)],
        m[(0, 1)],
        m[(0, 2)],
        m[(1, 2)],
    )
}

/// The servo of one coordinate: natural frequency `hz` and damping ratio `zeta` for a
/// load of `inertia` (kg or kg·m²), limited to `max` (N or N·m).
fn servo(inertia: f64, hz: f64, zeta: f64, max: f64) -> Motor {
    let w = 2.0 * std::f64::consts::PI * hz;
    Motor {
        target_position: Some(0.0),
        target_velocity: 0.0,
        stiffness: inertia * w * w,
        damping: 2.0 * zeta * inertia * w,
        max_force: max,
    }
}

/// Rod `rod` of `table` as an articulated system: centred, feet down, at rest, with its
/// shapes, the hand's two servos and the slide's travel limits.
pub(crate) fn rod_system(
    table: &Table,
    rod: usize,
    settings: &ArenaSettings,
    man: Material,
) -> Result<ArticulatedSystem, ArenaError> {
    let spec = &table.rods[rod];
    let parts = parts(table, rod, man);
    let (_, mass) = Compound::new(&parts).map_err(|_| ArenaError::Rod { rod })?;
    let inertia = Inertia::from_com(mass.mass, com(&mass), link_inertia(&mass));
    let i_axis = inertia.i.yy;
    let mut tree = ArticulatedTree::new(Vec3::new(0.0, 0.0, -GRAVITY_M_PER_S2));
    tree.add_body(
        format!("rod {rod}"),
        None,
        SE3::from_translation(Vec3::new(spec.x_m, 0.0, table.field.rod_height_m)),
        Cylindrical::new(Vec3::y()),
        inertia,
    )
    .map_err(|_| ArenaError::Rod { rod })?;
    let half = spec.half_travel_m();
    let mut system = ArticulatedSystem::new(tree, vec![0.0, 0.0], vec![0.0, 0.0]);
    for p in parts {
        system = system.with_link_shape(0, p.shape, p.pose, p.material);
    }
    let zeta = settings.servo_damping_ratio;
    Ok(system
        .with_motor(
            SPIN,
            servo(i_axis, settings.servo_hertz, zeta, settings.hand_torque_n_m),
        )
        .with_motor(
            SLIDE,
            servo(mass.mass, settings.servo_hertz, zeta, settings.hand_force_n),
        )
        .with_limits(SLIDE, -half, half))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rod_weighs_its_bar_and_its_men() {
        let table = Table::standard();
        for rod in 0..table.rods.len() {
            let (m, i) = rod_mass_and_axial_inertia(&table, rod);
            let c = table.character_of(rod);
            let men = table.rods[rod].men as f64 * c.mass_kg;
            let bar = m - men;
            // A 16 mm × 1.5 mm steel tube: 0.536 kg per metre.
            let per_m = bar / (2.0 * bar_half_length_m(&table, rod));
            assert!((per_m - 0.536).abs() < 0.005, "rod {rod}: {per_m} kg/m");
            // The men hang within their reach of the axis: I < Σ m reach² + the bar's.
            assert!(i > 0.0 && i < men * c.foot_reach_m.powi(2) + bar * 1e-4);
        }
    }
}

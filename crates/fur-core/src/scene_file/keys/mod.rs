//! Every setting of a scene, by section: each defined once, here.

mod animation;
mod drawing;
mod looks;
mod simulation;
mod view;

use super::Group;

/// Every section of a scene file, in the order a saved scene writes them.
pub const GROUPS: &[&Group] = &[
    &view::IMAGE,
    &view::CAMERA,
    &view::GROOM,
    &drawing::RENDER,
    &looks::LIGHT,
    &looks::FIBRE,
    &looks::SHADOWS,
    &simulation::SIMULATION,
    &simulation::COLLISION,
    &animation::MOTION,
    &animation::ANIMATION,
];

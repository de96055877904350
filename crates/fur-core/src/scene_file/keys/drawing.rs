//! `[render]`: how the fur is drawn, the levers that trade speed for image quality
//! (`fur bench` measures each). Each setting is declared beside the field of the
//! drawing style it sets ([`crate::render::style::SETTINGS`]); the scene reaches them
//! through its style (`SceneOptions::draw`).

use crate::render::style;
use crate::scene_file::{Access, Group, Setting};

pub const RENDER: Group = Group {
    section: "render",
    heading: "Drawing",
    settings: &DRAWING,
};

/// The style's settings, as the scene reaches them.
const DRAWING: [Setting; style::SETTINGS.len()] = {
    let first = &style::SETTINGS[0];
    let mut all = [first.through(Access::Style(first.access)); style::SETTINGS.len()];
    let mut i = 1;
    while i < all.len() {
        let setting = &style::SETTINGS[i];
        all[i] = setting.through(Access::Style(setting.access));
        i += 1;
    }
    all
};

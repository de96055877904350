//! The viewer's animation controls: which clip a skinned body plays, its speed and the
//! clip time (a scrub), from the panel and the keys (`c` next clip, `[` / `]` slower and
//! faster; Space pauses the simulation and with it the clip).

use fur_core::skinning::{AnimationSpec, Playback};
use fur_gpu::session::FurSession;

/// Shows the animation section of the panel when the body is skinned.
pub(super) fn panel(ui: &mut egui::Ui, session: &mut FurSession) {
    let time = session.sim.time;
    let Some(skinned) = session.sim.skinned.as_mut() else {
        return;
    };
    let rig = &skinned.body.rig;
    let playback = &mut skinned.playback;
    egui::CollapsingHeader::new("animation")
        .default_open(true)
        .show(ui, |ui| {
            let name = |c: Option<usize>| {
                c.and_then(|c| rig.clips.get(c))
                    .map_or("rest pose".to_string(), |c| c.name.clone())
            };
            egui::ComboBox::from_label("clip")
                .selected_text(name(playback.clip))
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut playback.clip, None, "rest pose");
                    for (i, clip) in rig.clips.iter().enumerate() {
                        ui.selectable_value(&mut playback.clip, Some(i), clip.name.clone());
                    }
                });
            ui.add(egui::Slider::new(&mut playback.speed, 0.0..=4.0).text("speed"));
            let duration = playback
                .clip
                .and_then(|c| rig.clips.get(c))
                .map_or(0.0, |c| c.duration());
            if duration > 0.0 {
                let mut t = playback.clip_time(rig, time);
                if ui
                    .add(egui::Slider::new(&mut t, 0.0..=duration).text("clip time (s)"))
                    .changed()
                {
                    scrub(playback, time, t);
                }
            }
            ui.checkbox(&mut playback.looping, "loop");
            ui.checkbox(&mut playback.in_place, "walk in place");
        });
}

/// Sets the clip time at simulated time `now` to `t`.
fn scrub(playback: &mut Playback, now: f64, t: f32) {
    playback.start = t - (f64::from(playback.speed) * now) as f32;
}

/// A key press on the animation: `c` plays the next clip, `[` and `]` change speed.
pub(super) fn key(session: &mut FurSession, key: &str) {
    let Some(skinned) = session.sim.skinned.as_mut() else {
        return;
    };
    let count = skinned.body.rig.clips.len();
    let p = &mut skinned.playback;
    match key {
        "c" if count > 0 => {
            p.clip = match p.clip {
                Some(c) if c + 1 < count => Some(c + 1),
                Some(_) => None,
                None => Some(0),
            }
        }
        "[" => p.speed = (p.speed / 1.25).max(0.01),
        "]" => p.speed = (p.speed * 1.25).min(100.0),
        _ => {}
    }
}

/// The session's animation as a scene file keeps it.
pub(super) fn spec(session: &FurSession) -> AnimationSpec {
    let Some(skinned) = session.sim.skinned.as_ref() else {
        return AnimationSpec::default();
    };
    let rig = &skinned.body.rig;
    let p = &skinned.playback;
    AnimationSpec {
        clip: Some(
            p.clip
                .and_then(|c| rig.clips.get(c))
                .map_or("none".to_string(), |c| c.name.clone()),
        ),
        speed: p.speed,
        // The clip time the saved scene starts at: where the viewer is now.
        start: p.clip_time(rig, session.sim.time),
        looping: p.looping,
        in_place: p.in_place,
    }
}

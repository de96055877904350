//! The image, the camera and the groom.

use crate::render::style::DENSITY;
use crate::scene_file::value::field;
use crate::scene_file::{Access, Effect, FieldValue, Flag, Group, Kind, Panel, Setting, Value};
use crate::setting::Accessor;

pub const IMAGE: Group = Group {
    section: "image",
    heading: "Image",
    settings: &[
        Setting {
            key: "width",
            flag: Flag::Long("width"),
            label: "image size, width",
            help: "Image width (the viewer's window width)",
            units: "px",
            kind: Kind::integer(1, 16384),
            effect: Effect::Restart,
            ..field!(width)
        },
        Setting {
            key: "height",
            flag: Flag::Long("height"),
            label: "image size, height",
            help: "Image height (the viewer's window height)",
            units: "px",
            kind: Kind::integer(1, 16384),
            effect: Effect::Restart,
            ..field!(height)
        },
        Setting {
            key: "show",
            flag: Flag::Long("show"),
            label: "show",
            help: "Which stage of the pipeline the image shows: `lit` (the final image, lit \
                   by `lighting_model`), \
                   `masters` (only the master hairs, as lines coloured by master index, with \
                   the body), `interpolated` (every hair unlit, a flat colour per source \
                   triangle), `density` (the body as the tessellator divides it, each \
                   triangle coloured by its inner level, blue 1 to red the device's \
                   largest, with a legend; culled triangles hatched grey), `lod` (hue: the \
                   share of segments the vertex LOD keeps, red all to blue one; darker \
                   where the density LOD thins the hairs), `simulation` (the master hairs \
                   coloured by how far the simulation moved them from rest, blue none to \
                   red a quarter of their length; white where collision pushed them), \
                   `shadow` (every hair by the self-shadowing term alone: grey under \
                   Kajiya–Kay, the light the coat's layers let through in its colour under \
                   the Marschner model), \
                   `ownership` (each hair in its drawing triangle's colour: dim inside, \
                   bright on an edge, white at a corner) or `tiles` (the compute \
                   rasteriser's screen tiles, each coloured by the segments it lists, blue \
                   one to red 4,096, evenly in powers of two, with a legend; the strands \
                   are drawn in compute whatever `raster` says)",
            kind: Kind::Choice(&[
                "lit",
                "masters",
                "interpolated",
                "density",
                "lod",
                "simulation",
                "shadow",
                "ownership",
                "tiles",
            ]),
            panel: Panel::Plain,
            ..field!(options.show)
        },
        Setting {
            key: "arrows",
            flag: Flag::Long("arrows"),
            label: "arrows (simulation view)",
            help: "In the `simulation` view, the correction one step of the simulation made \
                   to each master-hair vertex in the frame's last substep, drawn from where \
                   the step found the vertex (dark) to where it left it (bright), magnified \
                   `arrow_scale` times: `none`, `integrate`, `global` (shape), `local` \
                   (shape), `length`, `wind` or `collision`. Step through frames in the \
                   viewer (pause: space, one step: n) to follow them",
            kind: Kind::Choice(&[
                "none",
                "integrate",
                "global",
                "local",
                "length",
                "wind",
                "collision",
            ]),
            panel: Panel::Plain,
            ..field!(options.arrows)
        },
        Setting {
            key: "arrow_scale",
            flag: Flag::Long("arrow-scale"),
            label: "arrow scale",
            help: "How many times its length the simulation view draws each step's correction",
            units: "×",
            kind: Kind::positive(10_000.0),
            panel: Panel::Slider {
                min: 1.0,
                max: 1000.0,
                log: true,
            },
            ..field!(options.arrow_scale)
        },
    ],
};

pub const CAMERA: Group = Group {
    section: "camera",
    heading: "Camera",
    settings: &[
        Setting {
            key: "yaw",
            flag: Flag::Long("yaw"),
            label: "camera yaw",
            help: "Camera orbit angle around the vertical axis",
            units: "°",
            kind: Kind::within(-1e6, 1e6),
            ..field!(options.yaw_deg)
        },
        Setting {
            key: "pitch",
            flag: Flag::Long("pitch"),
            label: "camera pitch",
            help: "Camera elevation",
            units: "°",
            kind: Kind::within(-1e6, 1e6),
            ..field!(options.pitch_deg)
        },
        Setting {
            key: "distance",
            flag: Flag::Long("distance"),
            label: "camera distance",
            help: "Camera distance in bounding radii of the model",
            units: "bounding radii",
            kind: Kind::span(crate::span::Span::positive()),
            unset: Some("framing the whole model"),
            ..field!(options.distance)
        },
        Setting {
            key: "fov",
            flag: Flag::Long("fov"),
            label: "field of view",
            help: "Vertical field of view",
            units: "°",
            kind: Kind::span(crate::scene_file::FOV_DEG),
            ..field!(options.fov_deg)
        },
    ],
};

pub const GROOM: Group = Group {
    section: "groom",
    heading: "Groom",
    settings: &[
        Setting {
            key: "hair_length",
            flag: Flag::Long("hair-length"),
            label: "hair length",
            help: "Hair length as a fraction of the model's bounding radius",
            units: "bounding radii",
            kind: Kind::span(crate::span::Span::positive()),
            effect: Effect::Regrow,
            panel: Panel::Slider {
                min: 0.02,
                max: 1.0,
                log: false,
            },
            ..field!(options.hair_length)
        },
        Setting {
            key: "segments",
            flag: Flag::Long("segments"),
            label: "segments",
            help: "Segments per master hair",
            kind: Kind::integer(1, crate::scene::groom::MAX_SEGMENTS),
            effect: Effect::Regrow,
            panel: Panel::Slider {
                min: 1.0,
                max: 63.0,
                log: false,
            },
            ..field!(options.segments)
        },
        Setting {
            key: "density_scale",
            flag: Flag::Long("density-scale"),
            label: "density scale",
            help: "Multiplies the interpolated-hair density",
            kind: Kind::span(crate::render::style::spans::POSITIVE),
            panel: Panel::Slider {
                min: 0.01,
                max: 10.0,
                log: true,
            },
            // The scene's density ([`crate::render::FurStyle::density`], per square
            // bounding radius) as a multiple of the default's.
            access: Access::Style(Accessor {
                get: |s| Value::Number(f64::from(s.density) / f64::from(DENSITY)),
                set: |s, v| {
                    if let Some(scale) = f32::from_value(v) {
                        s.density = scale * DENSITY;
                    }
                },
            }),
            ..field!(options.draw.density)
        },
        Setting {
            key: "comb",
            flag: Flag::Long("comb"),
            label: "comb strength",
            help: "Comb strength, 0 = hairs stand along the normals",
            kind: Kind::span(crate::scene::groom::SHAPE),
            effect: Effect::Regrow,
            panel: Panel::Slider {
                min: 0.0,
                max: 4.0,
                log: false,
            },
            ..field!(options.comb)
        },
        Setting {
            key: "thickness_limit",
            flag: Flag::Long("thickness-limit"),
            label: "thickness limit",
            help: "Hairs are at most this many times the model's local half-thickness long, \
                   so thin parts are not buried; 0 = off",
            kind: Kind::span(crate::scene::groom::SHAPE),
            effect: Effect::Regrow,
            panel: Panel::Slider {
                min: 0.0,
                max: 2.0,
                log: false,
            },
            ..field!(options.thickness_limit)
        },
        Setting {
            key: "flow",
            flag: Flag::Long("flow"),
            label: "flow",
            help: "How grown fur lies: `body` (along the body from its head end, down every \
                   limb; a skinned body's along its bones; thin parts lie flat) or \
                   `direction` (towards one constant direction, the comb of earlier \
                   versions)",
            kind: Kind::Choice(&["body", "direction"]),
            effect: Effect::Regrow,
            panel: Panel::Plain,
            ..field!(options.flow)
        },
        Setting {
            key: "flow_from",
            flag: Flag::Long("flow-from"),
            label: "flow's head end",
            help: "Where the body's flow starts: `auto` (the end of the body's longest axis \
                   facing +z, glTF's front; an axis across z takes its +y end, then +x), \
                   an axis end (`+x`, `-z`…) or the surface nearest a point x,y,z",
            kind: Kind::Place,
            effect: Effect::Regrow,
            ..field!(options.flow_from)
        },
        Setting {
            key: "curl",
            flag: Flag::Long("curl"),
            label: "curl",
            help: "Curl radius as a fraction of the segment length",
            kind: Kind::span(crate::scene::groom::SHAPE),
            effect: Effect::Regrow,
            panel: Panel::Slider {
                min: 0.0,
                max: 2.0,
                log: false,
            },
            ..field!(options.curl)
        },
        Setting {
            key: "file",
            flag: Flag::Long("groom"),
            label: "groom file",
            help: "Guide curves to make the master hairs from, instead of growing them: USD \
                   (.usda, .usdc, .usdz), cyHair (.hair) or TressFX (.tfx), in the model's \
                   rest space; a path in a scene file is relative to the scene file",
            kind: Kind::Text,
            unset: Some("grown from the mesh"),
            effect: Effect::Regrow,
            ..field!(options.groom_file)
        },
        Setting {
            key: "outside",
            flag: Flag::Long("groom-outside"),
            label: "outside the groom",
            help: "What vertices away from every guide get: `bald` (a short stub; \
                   triangles between stubs draw no hair) or `grow` (the grown fur)",
            kind: Kind::Choice(&["bald", "grow"]),
            effect: Effect::Regrow,
            ..field!(options.groom_outside)
        },
        Setting {
            key: "mode",
            flag: Flag::Long("groom-mode"),
            label: "groom mode",
            help: "How the guides become hairs: `blend` (each vertex near the groom blends its \
                   nearest guides into a master hair, and hairs are interpolated between \
                   masters) or `draw` (each guide is drawn as it is, one hair per guide, for \
                   grooms that are already dense)",
            kind: Kind::Choice(&["blend", "draw"]),
            effect: Effect::Regrow,
            ..field!(options.groom_mode)
        },
    ],
};

#[cfg(test)]
mod tests {
    use crate::render::stage::Arrows;
    use crate::render::Stage;
    use crate::scene_file::Kind;

    fn choices(key: &str) -> Vec<&'static str> {
        let setting = super::IMAGE
            .settings
            .iter()
            .find(|s| s.key == key)
            .unwrap_or_else(|| panic!("no setting `{key}`"));
        match setting.kind {
            Kind::Choice(names) => names.to_vec(),
            _ => panic!("`{key}` is not a choice"),
        }
    }

    /// `show` and `arrows` offer exactly the views and arrows there are, in their order
    /// (a view added to `Stage::ALL` and not here, or the other way round, fails).
    #[test]
    fn the_image_settings_offer_every_view_and_every_arrow() {
        let stages: Vec<&str> = Stage::ALL.iter().map(|s| s.name()).collect();
        assert_eq!(choices("show"), stages);
        let arrows: Vec<&str> = Arrows::all().map(Arrows::name).collect();
        assert_eq!(choices("arrows"), arrows);
        let outside = super::GROOM
            .settings
            .iter()
            .find(|s| s.key == "outside")
            .map(|s| s.kind);
        let names: Vec<&str> = crate::scene::Outside::ALL
            .iter()
            .map(|o| o.name())
            .collect();
        assert!(matches!(outside, Some(Kind::Choice(n)) if n.to_vec() == names));
        let mode = super::GROOM
            .settings
            .iter()
            .find(|s| s.key == "mode")
            .map(|s| s.kind);
        let names: Vec<&str> = crate::scene::GroomMode::ALL
            .iter()
            .map(|m| m.name())
            .collect();
        assert!(matches!(mode, Some(Kind::Choice(n)) if n.to_vec() == names));
        let preset = super::super::looks::LIGHT
            .settings
            .iter()
            .find(|s| s.key == "fur_preset")
            .map(|s| s.kind);
        let names: Vec<&str> = crate::render::FurPreset::ALL
            .iter()
            .map(|p| p.name())
            .collect();
        assert!(matches!(preset, Some(Kind::Choice(n)) if n.to_vec() == names));
    }
}

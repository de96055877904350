//! How the fur is drawn: the levers that trade speed for image quality (`fur bench`
//! measures each).

use crate::render::style::{spans, SAMPLE_COUNTS, TILE_CHOICES};
use crate::scene_file::value::field;
use crate::scene_file::{Flag, Group, Kind, Panel, Setting};

pub const RENDER: Group = Group {
    section: "render",
    heading: "Drawing",
    settings: &[
        Setting {
            key: "samples",
            flag: Flag::Long("samples"),
            label: "samples per pixel",
            help: "Samples per pixel: 1 (no MSAA; lines then blend their coverage) or an MSAA \
                   count the device supports (lavapipe: 1 and 4)",
            kind: Kind::OneOf(&SAMPLE_COUNTS),
            panel: Panel::Plain,
            ..field!(options.draw.samples)
        },
        Setting {
            key: "raster",
            flag: Flag::Long("raster"),
            label: "strand rasteriser",
            help:
                "What draws the strands the geometry stage makes: `hardware` (the fixed-function \
                   rasteriser: lines or ribbons) or `compute` (compute passes: strands binned to \
                   screen tiles, exact coverage, the nearest fragments of each pixel blended \
                   front to back)",
            kind: Kind::Choice(&["hardware", "compute"]),
            panel: Panel::Plain,
            ..field!(options.draw.raster)
        },
        Setting {
            key: "nearest",
            flag: Flag::Long("nearest"),
            label: "fragments in order",
            help: "With `raster = \"compute\"`: the fragments each pixel keeps in depth order \
                   and blends front to back; the rest are blended in an order-free tail. More \
                   is closer to the true order, and costs more",
            kind: Kind::Integer {
                min: 1,
                max: crate::render::MAX_NEAREST,
                zero: false,
            },
            panel: Panel::Plain,
            ..field!(options.draw.nearest)
        },
        Setting {
            key: "tile",
            flag: Flag::Long("tile"),
            label: "tile side (px)",
            help: "With `raster = \"compute\"`: the side of the screen tiles strands are binned \
                   to, pixels; 0 takes the default side. A pixel \
                   walks its tile's list: a smaller tile lists fewer segments a pixel, and \
                   lists each segment in more tiles",
            kind: Kind::OneOf(&TILE_CHOICES),
            panel: Panel::Plain,
            ..field!(options.draw.tile)
        },
        Setting {
            key: "primitive",
            flag: Flag::Long("primitive"),
            label: "hair primitive",
            help: "What each hair is drawn as: `lines` (coverage in alpha), `ribbons` (true \
                   width), or `auto`: ribbons for hairs at least --ribbon-above pixels wide at \
                   the root, lines for the rest",
            kind: Kind::Choice(&["ribbons", "lines", "auto"]),
            panel: Panel::Plain,
            ..field!(options.draw.primitive)
        },
        Setting {
            key: "ribbon_above",
            flag: Flag::Long("ribbon-above"),
            label: "ribbon threshold",
            help: "Root width from which `auto` draws ribbons",
            units: "px",
            kind: Kind::span(spans::PIXELS),
            panel: Panel::Slider {
                min: 0.0,
                max: 8.0,
                log: false,
            },
            ..field!(options.draw.ribbon_above_px)
        },
        Setting {
            key: "shading",
            flag: Flag::Long("shading"),
            label: "shading rate",
            help: "Where the lighting runs: `vertex` (per strand vertex, geometry stage) or \
                   `fragment`",
            kind: Kind::Choice(&["vertex", "fragment"]),
            panel: Panel::Plain,
            ..field!(options.draw.shading)
        },
        Setting {
            key: "vertex_lod",
            flag: Flag::Long("vertex-lod"),
            label: "vertex LOD tolerance",
            help: "Vertex LOD tolerance: a strand vertex is skipped when the segment drawn \
                   instead passes within this distance of it, width included; 0 draws every \
                   vertex",
            units: "px",
            kind: Kind::span(spans::PIXELS),
            panel: Panel::Slider {
                min: 0.0,
                max: 2.0,
                log: true,
            },
            ..field!(options.draw.vertex_lod_px)
        },
        Setting {
            key: "lod_distance",
            flag: Flag::Long("lod-distance"),
            label: "full-density distance",
            help: "Full-density distance: farther away the density falls with the square of \
                   the distance",
            units: "bounding radii",
            kind: Kind::span(spans::POSITIVE),
            panel: Panel::Slider {
                min: 0.1,
                max: 100.0,
                log: true,
            },
            ..field!(options.draw.lod_distance)
        },
        Setting {
            key: "thickness_compensation",
            flag: Flag::Long("thickness-compensation"),
            label: "thickness compensation",
            help: "Widen hairs the density LOD thins out, so coverage is kept",
            kind: Kind::Bool,
            panel: Panel::Plain,
            ..field!(options.draw.thickness_compensation)
        },
        Setting {
            key: "hair_width",
            flag: Flag::Long("hair-width"),
            label: "hair width",
            help: "Hair width at the root",
            units: "bounding radii",
            kind: Kind::span(spans::POSITIVE),
            panel: Panel::Slider {
                min: 1e-4,
                max: 0.05,
                log: true,
            },
            ..field!(options.draw.hair_width)
        },
        Setting {
            key: "min_pixel_width",
            flag: Flag::Long("min-pixel-width"),
            label: "minimum hair width",
            help: "Hairs are drawn at least this wide; thinner ones cover by their true width \
                   (thin-hair AA)",
            units: "px",
            kind: Kind::span(spans::MIN_PIXEL_WIDTH),
            panel: Panel::Slider {
                min: 0.0,
                max: 4.0,
                log: false,
            },
            ..field!(options.draw.min_pixel_width)
        },
        Setting {
            key: "jitter",
            flag: Flag::Long("jitter"),
            label: "jitter",
            help: "Random tip offset of each interpolated hair",
            units: "bounding radii",
            kind: Kind::span(spans::JITTER),
            panel: Panel::Slider {
                min: 0.0,
                max: 0.2,
                log: false,
            },
            ..field!(options.draw.jitter)
        },
        Setting {
            key: "length_jitter",
            flag: Flag::Long("length-jitter"),
            label: "length jitter",
            help: "Random shortening of each interpolated hair, as a fraction of its length",
            kind: Kind::span(spans::LENGTH_JITTER),
            panel: Panel::Slider {
                min: 0.0,
                max: 1.0,
                log: false,
            },
            ..field!(options.draw.length_jitter)
        },
        Setting {
            key: "cull",
            flag: Flag::Long("cull"),
            label: "culling",
            help: "Skip triangles facing away or off screen before tessellating them",
            kind: Kind::Bool,
            panel: Panel::Plain,
            ..field!(options.draw.cull)
        },
        Setting {
            key: "cull_margin",
            flag: Flag::Long("cull-margin"),
            label: "cull margin",
            help: "How far a triangle may face away before its hairs are culled: culled when \
                   cos(normal, view) < −margin; hairs on triangles just past the silhouette \
                   still show, so 0 loses them and 1 culls by the screen's bounds only",
            kind: Kind::span(spans::CULL_MARGIN),
            panel: Panel::Slider {
                min: 0.0,
                max: 1.0,
                log: false,
            },
            ..field!(options.draw.cull_margin)
        },
        Setting {
            key: "thin_hair_aa",
            flag: Flag::Long("thin-hair-aa"),
            label: "thin-hair anti-aliasing",
            help: "Hairs thinner than the minimum width cover their pixels by their true width \
                   (a dithered sample mask under MSAA, blending at 1 sample)",
            kind: Kind::Bool,
            panel: Panel::Plain,
            ..field!(options.draw.thin_hair_aa)
        },
    ],
};

//! The drawing's choices the scene file names: what the geometry stage emits for each
//! hair, where it is lit, and what rasterises the strands.

/// What the geometry stage emits for each hair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Primitive {
    /// Line strips carrying their coverage as alpha for hairs narrower than
    /// [`FurStyle::ribbon_above_px`](super::FurStyle::ribbon_above_px) at the root, ribbons for the wider ones.
    Auto,
    /// Line strips for every hair.
    Lines,
    /// Camera-facing ribbons of the true width for every hair.
    #[default]
    Ribbons,
}

impl Primitive {
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Lines => "lines",
            Self::Ribbons => "ribbons",
        }
    }
}

impl std::str::FromStr for Primitive {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "auto" => Ok(Self::Auto),
            "lines" => Ok(Self::Lines),
            "ribbons" => Ok(Self::Ribbons),
            _ => Err(format!("expected auto, lines or ribbons, got `{s}`")),
        }
    }
}

/// Where Kajiya–Kay is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Shading {
    /// Per emitted strand vertex, in the geometry stage (colours interpolated).
    #[default]
    Vertex,
    /// Per fragment.
    Fragment,
}

impl Shading {
    pub fn name(self) -> &'static str {
        match self {
            Self::Vertex => "vertex",
            Self::Fragment => "fragment",
        }
    }
}

impl std::str::FromStr for Shading {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "vertex" => Ok(Self::Vertex),
            "fragment" => Ok(Self::Fragment),
            _ => Err(format!("expected vertex or fragment, got `{s}`")),
        }
    }
}

/// What draws the strands the geometry stage makes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Raster {
    /// The fixed-function rasteriser: the geometry stage emits lines or ribbons.
    Hardware,
    /// Compute passes (the default): the geometry stage writes its strands into
    /// buffers, which are binned to screen tiles and drawn with exact coverage, the
    /// nearest fragments of each pixel blended front to back (the CPU twin:
    /// [`crate::render::strand_raster`]). On lavapipe the default blob's frame costs
    /// less than the fixed-function one's and errs less against the supersampled
    /// reference (`fur bench --only raster`).
    #[default]
    Compute,
}

impl Raster {
    pub fn name(self) -> &'static str {
        match self {
            Self::Hardware => "hardware",
            Self::Compute => "compute",
        }
    }
}

impl std::str::FromStr for Raster {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "hardware" => Ok(Self::Hardware),
            "compute" => Ok(Self::Compute),
            _ => Err(format!("expected hardware or compute, got `{s}`")),
        }
    }
}

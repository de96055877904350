//! Reading accessors: every one checked against its buffer view and buffer (offset +
//! stride × (count − 1) + element size within the view, the view within its buffer)
//! before anything is allocated for it, and its type and component type checked
//! against what it is used for.

use gltf::json::accessor::{ComponentType, Type};
use gltf::json::validation::Checked;

use super::source::Source;

/// Which component types an accessor may hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Allowed {
    /// 32-bit floats only.
    Float,
    /// Floats, or normalised unsigned bytes and shorts (and signed ones when `signed`),
    /// read as floats in [0, 1] ([-1, 1] for signed ones).
    FloatOrNormalized { signed: bool },
    /// Unsigned bytes and shorts (and 32-bit unsigned ints when `wide`), as integers.
    Unsigned { wide: bool },
}

/// Where an accessor's elements lie: `count` elements of `dims` components, the first
/// at `bytes[0]`, each `stride` bytes after the previous.
struct Layout<'s> {
    bytes: &'s [u8],
    stride: usize,
    count: usize,
    component: ComponentType,
    dims: usize,
}

impl Source<'_> {
    /// The number of elements accessor `index` declares (for budgets before reading).
    pub fn accessor_count(&self, index: usize, what: &str) -> Result<u64, String> {
        self.root
            .accessors
            .get(index)
            .map(|a| a.count.0)
            .ok_or_else(|| self.missing(index, what))
    }

    /// Checks, before reading it, that accessor `index` has one element per vertex.
    pub fn expect_count(&self, index: usize, what: &str, vertices: usize) -> Result<(), String> {
        let declared = self.accessor_count(index, what)?;
        if declared == vertices as u64 {
            Ok(())
        } else {
            Err(format!(
                "{} has {declared} elements for {vertices} vertices",
                label(index, what)
            ))
        }
    }

    /// Accessor `index` as floats, `dims(ty)` per element, flattened; `what` names its
    /// use in messages ("POSITION of mesh 0 primitive 0").
    pub fn floats(
        &self,
        index: usize,
        what: &str,
        ty: Type,
        allowed: Allowed,
    ) -> Result<Vec<f32>, String> {
        let layout = self.layout(index, what, ty, allowed, usize::MAX)?;
        let size = component_size(layout.component);
        let convert = |b: &[u8]| -> f32 {
            match layout.component {
                ComponentType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
                ComponentType::U8 => f32::from(b[0]) / 255.0,
                ComponentType::U16 => f32::from(u16::from_le_bytes([b[0], b[1]])) / 65535.0,
                ComponentType::I8 => (f32::from(b[0] as i8) / 127.0).max(-1.0),
                ComponentType::I16 => {
                    (f32::from(i16::from_le_bytes([b[0], b[1]])) / 32767.0).max(-1.0)
                }
                ComponentType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
            }
        };
        gather(&layout, size, convert)
    }

    /// Accessor `index` as unsigned integers, flattened.
    pub fn uints(
        &self,
        index: usize,
        what: &str,
        ty: Type,
        allowed: Allowed,
    ) -> Result<Vec<u32>, String> {
        let layout = self.layout(index, what, ty, allowed, usize::MAX)?;
        let size = component_size(layout.component);
        gather(&layout, size, |b: &[u8]| match layout.component {
            ComponentType::U8 => u32::from(b[0]),
            ComponentType::U16 => u32::from(u16::from_le_bytes([b[0], b[1]])),
            _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        })
    }

    /// Up to `limit` float matrices (MAT4) of accessor `index`, column-major.
    pub fn matrices(&self, index: usize, what: &str, limit: usize) -> Result<Vec<f32>, String> {
        let layout = self.layout(index, what, Type::Mat4, Allowed::Float, limit)?;
        gather(&layout, 4, |b: &[u8]| {
            f32::from_le_bytes([b[0], b[1], b[2], b[3]])
        })
    }

    fn missing(&self, index: usize, what: &str) -> String {
        format!(
            "{} does not exist (the file has {} accessors)",
            label(index, what),
            self.root.accessors.len()
        )
    }

    fn layout(
        &self,
        index: usize,
        what: &str,
        ty: Type,
        allowed: Allowed,
        limit: usize,
    ) -> Result<Layout<'_>, String> {
        let accessor = self
            .root
            .accessors
            .get(index)
            .ok_or_else(|| self.missing(index, what))?;
        let name = label(index, what);
        if accessor.sparse.is_some() {
            return Err(format!(
                "{name} is sparse: sparse accessors are not supported"
            ));
        }
        let actual = match accessor.type_ {
            Checked::Valid(t) => t,
            Checked::Invalid => return Err(format!("{name} has an unknown type")),
        };
        if actual != ty {
            return Err(format!(
                "{name} is {}, expected {}",
                type_name(actual),
                type_name(ty)
            ));
        }
        let component = match accessor.component_type {
            Checked::Valid(c) => c.0,
            Checked::Invalid => return Err(format!("{name} has an unknown component type")),
        };
        let fits = match allowed {
            Allowed::Float => component == ComponentType::F32,
            Allowed::FloatOrNormalized { signed } => match component {
                ComponentType::F32 => true,
                ComponentType::U8 | ComponentType::U16 => accessor.normalized,
                ComponentType::I8 | ComponentType::I16 => signed && accessor.normalized,
                ComponentType::U32 => false,
            },
            Allowed::Unsigned { wide } => match component {
                ComponentType::U8 | ComponentType::U16 => true,
                ComponentType::U32 => wide,
                _ => false,
            },
        };
        if !fits {
            let normalized = if accessor.normalized {
                "normalised "
            } else {
                ""
            };
            return Err(format!(
                "{name} holds {normalized}{} components; expected {}",
                component_name(component),
                allowed_name(allowed)
            ));
        }
        let Some(view_index) = accessor.buffer_view.map(|v| v.value()) else {
            return Err(format!("{name} has no bufferView"));
        };
        let view = self.root.buffer_views.get(view_index).ok_or_else(|| {
            format!(
                "{name} refers to buffer view {view_index}, which does not exist (the file \
                 has {})",
                self.root.buffer_views.len()
            )
        })?;
        let dims = dims(ty);
        let element = (dims * component_size(component)) as u64;
        let stride = view.byte_stride.map_or(element, |s| s.0 as u64);
        if stride < element {
            return Err(format!(
                "{name} has {element}-byte elements, but buffer view {view_index}'s byteStride \
                 is {stride}"
            ));
        }
        let offset = accessor.byte_offset.map_or(0, |o| o.0);
        let count = accessor.count.0;
        let reach = if count == 0 {
            u128::from(offset)
        } else {
            u128::from(offset) + u128::from(stride) * u128::from(count - 1) + u128::from(element)
        };
        if reach > u128::from(view.byte_length.0) {
            return Err(format!(
                "{name} reaches byte {reach} of a {}-byte buffer view {view_index} ({count} \
                 elements of {element} bytes, {stride} apart, from byte {offset})",
                view.byte_length.0
            ));
        }
        let bytes = self
            .view(view_index)
            .map_err(|e| format!("{name} cannot be read: {e}"))?;
        // `reach` fits the view, and the view fits the bytes held: all below usize::MAX.
        let bytes = bytes.get(offset as usize..).unwrap_or_default();
        Ok(Layout {
            bytes,
            stride: stride as usize,
            count: (count as usize).min(limit),
            component,
            dims,
        })
    }
}

/// Reads every component of every element with `convert` (given exactly `size` bytes).
fn gather<T>(layout: &Layout, size: usize, convert: impl Fn(&[u8]) -> T) -> Result<Vec<T>, String> {
    let mut out = Vec::with_capacity(layout.count * layout.dims);
    for e in 0..layout.count {
        for c in 0..layout.dims {
            let at = e * layout.stride + c * size;
            let bytes = layout
                .bytes
                .get(at..at + size)
                .ok_or("an accessor element lies outside its buffer view")?;
            out.push(convert(bytes));
        }
    }
    Ok(out)
}

fn label(index: usize, what: &str) -> String {
    format!("accessor {index} ({what})")
}

pub(super) fn dims(ty: Type) -> usize {
    match ty {
        Type::Scalar => 1,
        Type::Vec2 => 2,
        Type::Vec3 => 3,
        Type::Vec4 | Type::Mat2 => 4,
        Type::Mat3 => 9,
        Type::Mat4 => 16,
    }
}

fn component_size(c: ComponentType) -> usize {
    match c {
        ComponentType::I8 | ComponentType::U8 => 1,
        ComponentType::I16 | ComponentType::U16 => 2,
        ComponentType::U32 | ComponentType::F32 => 4,
    }
}

fn type_name(ty: Type) -> &'static str {
    match ty {
        Type::Scalar => "SCALAR",
        Type::Vec2 => "VEC2",
        Type::Vec3 => "VEC3",
        Type::Vec4 => "VEC4",
        Type::Mat2 => "MAT2",
        Type::Mat3 => "MAT3",
        Type::Mat4 => "MAT4",
    }
}

fn component_name(c: ComponentType) -> &'static str {
    match c {
        ComponentType::I8 => "signed byte",
        ComponentType::U8 => "unsigned byte",
        ComponentType::I16 => "signed short",
        ComponentType::U16 => "unsigned short",
        ComponentType::U32 => "unsigned int",
        ComponentType::F32 => "float",
    }
}

fn allowed_name(allowed: Allowed) -> &'static str {
    match allowed {
        Allowed::Float => "floats",
        Allowed::FloatOrNormalized { signed: false } => {
            "floats or normalised unsigned bytes or shorts"
        }
        Allowed::FloatOrNormalized { signed: true } => "floats or normalised bytes or shorts",
        Allowed::Unsigned { wide: false } => "unsigned bytes or shorts",
        Allowed::Unsigned { wide: true } => "unsigned bytes, shorts or ints",
    }
}

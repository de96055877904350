//! Structs both Rust and GLSL read: declared once, in Rust, by [`std140_struct!`],
//! which makes the Rust struct (`#[repr(C)]`, `Pod`) and its GLSL declaration
//! ([`Std140::glsl`]), each member with the first line of its doc comment. The shaders
//! include the declarations (`frame_block.glsl`, made by
//! [`super::frame_block::glsl`]); a test of the GPU layer checks every member's offset
//! in the compiled SPIR-V against the Rust one ([`Std140::members`]), so a layout std140
//! would lay out otherwise fails there.

use glam::{Mat4, Vec2, Vec3, Vec4};

/// A type a std140 member may have, and its GLSL name.
pub trait GlslType {
    /// Its GLSL type (`float`, `vec3`, a struct's name).
    fn glsl_type() -> String;
    /// Its array length, if it is an array.
    fn array_len() -> Option<usize> {
        None
    }
}

macro_rules! glsl_types {
    ($($t:ty => $name:literal),+ $(,)?) => {$(
        impl GlslType for $t {
            fn glsl_type() -> String {
                $name.into()
            }
        }
    )+};
}

glsl_types!(f32 => "float", u32 => "uint", Vec2 => "vec2", Vec3 => "vec3", Vec4 => "vec4", Mat4 => "mat4");

impl<T: GlslType, const N: usize> GlslType for [T; N] {
    fn glsl_type() -> String {
        T::glsl_type()
    }
    fn array_len() -> Option<usize> {
        Some(N)
    }
}

/// One member of a [`Std140`] struct.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Member {
    pub name: &'static str,
    /// Its byte offset in the Rust struct.
    pub offset: usize,
    pub glsl_type: String,
    pub array_len: Option<usize>,
    /// Its doc comment's first paragraph ([`summary`]).
    pub comment: String,
}

impl Member {
    /// Padding: in the Rust struct only (std140 rounds a struct up to 16 bytes itself).
    pub fn is_padding(&self) -> bool {
        self.name.starts_with('_')
    }
}

/// A declared struct as GLSL and the reflection test see it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Declared {
    /// Its GLSL name.
    pub name: &'static str,
    /// Its GLSL declaration ([`Std140::glsl`]).
    pub glsl: String,
    /// Every member, padding included.
    pub members: Vec<Member>,
}

/// `T` as [`Declared`].
pub fn declared<T: Std140>() -> Declared {
    Declared {
        name: T::NAME,
        glsl: T::glsl(),
        members: T::members(),
    }
}

/// A struct declared by [`std140_struct!`].
pub trait Std140: GlslType {
    /// Its GLSL name.
    const NAME: &'static str;
    /// Its doc comment's first line, for the GLSL comment above it.
    const SUMMARY: &'static str;
    /// Every member, padding included, in order.
    fn members() -> Vec<Member>;

    /// Its GLSL declaration, padding left out.
    fn glsl() -> String {
        let mut text = format!("// {}\nstruct {} {{\n", Self::SUMMARY.trim(), Self::NAME);
        for m in Self::members().iter().filter(|m| !m.is_padding()) {
            let array = m.array_len.map(|n| format!("[{n}]")).unwrap_or_default();
            let decl = format!("    {} {}{array};", m.glsl_type, m.name);
            match m.comment.as_str() {
                "" => text += &format!("{decl}\n"),
                comment => text += &format!("{decl:<34} // {comment}\n"),
            }
        }
        text + "};\n"
    }
}

/// A doc comment's first paragraph (its lines as `#[doc]` attributes hold them) on
/// one line, rustdoc's link brackets left out: a GLSL comment.
pub fn summary(lines: &[&str]) -> String {
    let paragraph: Vec<&str> = lines
        .iter()
        .map(|l| l.trim())
        .take_while(|l| !l.is_empty())
        .collect();
    paragraph.join(" ").replace("[`", "`").replace("`]", "`")
}

/// Declares a std140 struct for Rust and GLSL at once:
///
/// ```ignore
/// std140_struct! {
///     /// The master strands' texture.
///     pub struct StrandsBlock("Strands") {
///         pub vertices_per_strand: u32,
///         /// A master hair this short is a bald stub.
///         pub stub_length: f32,
///         pub _pad: [u32; 2],
///     }
/// }
/// ```
///
/// Members named `_…` are padding, left out of the GLSL.
#[macro_export]
macro_rules! std140_struct {
    (
        $(#[doc = $doc:literal])*
        pub struct $name:ident($glsl:literal) {
            $(
                $(#[doc = $field_doc:literal])*
                pub $field:ident: $ty:ty
            ),* $(,)?
        }
    ) => {
        $(#[doc = $doc])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name {
            $(
                $(#[doc = $field_doc])*
                pub $field: $ty,
            )*
        }

        impl $crate::render::std140::GlslType for $name {
            fn glsl_type() -> String {
                $glsl.into()
            }
        }

        impl $crate::render::std140::Std140 for $name {
            const NAME: &'static str = $glsl;
            const SUMMARY: &'static str = [$($doc),*][0];

            fn members() -> Vec<$crate::render::std140::Member> {
                use $crate::render::std140::GlslType;
                vec![$(
                    $crate::render::std140::Member {
                        name: stringify!($field),
                        offset: std::mem::offset_of!($name, $field),
                        glsl_type: <$ty>::glsl_type(),
                        array_len: <$ty>::array_len(),
                        comment: $crate::render::std140::summary(&[$($field_doc),*]),
                    }
                ),*]
            }
        }
    };
}
pub use std140_struct;

#[cfg(test)]
mod tests {
    use super::*;

    std140_struct! {
        /// A test struct.
        pub struct Probe("Probe") {
            /// The first [`paragraph`],
            /// on one line.
            ///
            /// Not this one.
            pub a: f32,
            pub b: Vec3,
            pub table: [Vec4; 3],
            pub _pad: [u32; 4],
        }
    }

    /// The GLSL names each member by its type, keeps arrays and the first doc line,
    /// and leaves the padding out; the offsets are Rust's.
    #[test]
    fn a_struct_is_declared_for_glsl_as_for_rust() {
        let glsl = Probe::glsl();
        assert!(
            glsl.starts_with("// A test struct.\nstruct Probe {\n"),
            "{glsl}"
        );
        assert!(glsl.contains("    float a;"), "{glsl}");
        assert!(
            glsl.contains("// The first `paragraph`, on one line.\n"),
            "{glsl}"
        );
        assert!(!glsl.contains("Not this one"), "{glsl}");
        assert!(glsl.contains("    vec3 b;\n"), "{glsl}");
        assert!(glsl.contains("    vec4 table[3];\n"), "{glsl}");
        assert!(!glsl.contains("_pad"), "{glsl}");
        let offsets: Vec<usize> = Probe::members().iter().map(|m| m.offset).collect();
        assert_eq!(offsets, vec![0, 4, 16, 64]);
    }
}

//! Descriptor sets declared once: [`bindings!`] makes, for a set, an enum of its
//! bindings numbered in order, each with the GLSL define that names its number, its
//! descriptor type and its stages. The render passes' sets (`render/bindings.rs`) and
//! the simulation's and skinning's kernels (`sim/kernel.rs`, `skinning/gpu.rs`) are
//! declared with it, so no binding number is typed twice.

/// Declares a set's bindings: an enum numbered in order, with each binding's define,
/// descriptor type and stages.
macro_rules! bindings {
    ($(#[$doc:meta])* $set:ident { $($(#[$bdoc:meta])* $name:ident = ($define:literal, $ty:ident, $stages:expr)),+ $(,)? }) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub(super) enum $set { $($(#[$bdoc])* $name),+ }

        impl $set {
            pub(super) const ALL: &'static [$set] = &[$($set::$name),+];

            /// The GLSL define that names its binding number.
            pub(super) fn define(self) -> &'static str {
                match self { $($set::$name => $define),+ }
            }

            /// Its descriptor type and the stages that read it.
            pub(super) fn layout(self) -> (::ash::vk::DescriptorType, ::ash::vk::ShaderStageFlags) {
                match self { $($set::$name => (::ash::vk::DescriptorType::$ty, $stages)),+ }
            }

            /// A write of this binding of `set` (its info still to add).
            pub(super) fn write(self, set: ::ash::vk::DescriptorSet) -> ::ash::vk::WriteDescriptorSet<'static> {
                ::ash::vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(self as u32)
                    .descriptor_type(self.layout().0)
            }

            /// Each binding's define with its number, for the shaders.
            pub(super) fn defines() -> impl Iterator<Item = (&'static str, String)> {
                Self::ALL.iter().map(|b| (b.define(), (*b as u32).to_string()))
            }

            /// The whole set's layout, in binding order.
            pub(super) fn set_layout() -> Vec<(::ash::vk::DescriptorType, ::ash::vk::ShaderStageFlags)> {
                Self::ALL.iter().map(|b| b.layout()).collect()
            }
        }
    };
}

pub(crate) use bindings;

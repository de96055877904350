//! What a compiled shader declares, read back from its SPIR-V (tests only): the
//! descriptor bindings it uses, with their types, and the member offsets of its
//! structs, so tests can check them against the Rust side's layouts and `#[repr(C)]`
//! structs instead of trusting comments.

use std::collections::{BTreeMap, HashMap};

use ash::vk;
use rspirv::dr::{Instruction, Operand};
use rspirv::spirv::{Decoration, Dim, Op, StorageClass};

/// A shader's declarations.
#[derive(Debug, Default)]
pub struct Reflection {
    /// (set, binding) → (variable name, descriptor type).
    pub bindings: BTreeMap<(u32, u32), (String, vk::DescriptorType)>,
    /// Struct name → its members' (name, offset), in order.
    pub structs: HashMap<String, Vec<(String, u32)>>,
}

fn id(op: &Operand) -> Option<u32> {
    match op {
        Operand::IdRef(id) => Some(*id),
        _ => None,
    }
}

fn literal(op: &Operand) -> Option<u32> {
    match op {
        Operand::LiteralBit32(v) => Some(*v),
        _ => None,
    }
}

/// `words` without the instructions that carry source text (OpSource,
/// OpSourceContinued, OpString, OpModuleProcessed): the compiler splits the embedded
/// source into strings at arbitrary bytes, which a UTF-8 reader refuses.
fn without_source(words: &[u32]) -> Vec<u32> {
    let mut out = words[..5.min(words.len())].to_vec();
    let mut at = 5;
    while at < words.len() {
        let count = (words[at] >> 16).max(1) as usize;
        let opcode = words[at] & 0xffff;
        let end = (at + count).min(words.len());
        if ![2, 3, 7, 330].contains(&opcode) {
            out.extend_from_slice(&words[at..end]);
        }
        at = end;
    }
    out
}

/// Reads `words` (SPIR-V compiled with debug names).
pub fn reflect(words: &[u32]) -> Reflection {
    let module = rspirv::dr::load_words(without_source(words)).expect("valid SPIR-V");
    let mut names: HashMap<u32, String> = HashMap::new();
    let mut member_names: HashMap<(u32, u32), String> = HashMap::new();
    for inst in &module.debug_names {
        match (inst.class.opcode, inst.operands.as_slice()) {
            (Op::Name, [target, Operand::LiteralString(name)]) => {
                names.insert(id(target).unwrap(), name.clone());
            }
            (Op::MemberName, [target, member, Operand::LiteralString(name)]) => {
                member_names.insert(
                    (id(target).unwrap(), literal(member).unwrap()),
                    name.clone(),
                );
            }
            _ => {}
        }
    }
    let mut sets: HashMap<u32, u32> = HashMap::new();
    let mut bindings: HashMap<u32, u32> = HashMap::new();
    let mut buffer_blocks: Vec<u32> = Vec::new();
    let mut offsets: HashMap<(u32, u32), u32> = HashMap::new();
    for inst in &module.annotations {
        match (inst.class.opcode, inst.operands.as_slice()) {
            (Op::Decorate, [target, Operand::Decoration(Decoration::DescriptorSet), v]) => {
                sets.insert(id(target).unwrap(), literal(v).unwrap());
            }
            (Op::Decorate, [target, Operand::Decoration(Decoration::Binding), v]) => {
                bindings.insert(id(target).unwrap(), literal(v).unwrap());
            }
            (Op::Decorate, [target, Operand::Decoration(Decoration::BufferBlock)]) => {
                buffer_blocks.push(id(target).unwrap());
            }
            (Op::MemberDecorate, [target, member, Operand::Decoration(Decoration::Offset), v]) => {
                offsets.insert(
                    (id(target).unwrap(), literal(member).unwrap()),
                    literal(v).unwrap(),
                );
            }
            _ => {}
        }
    }
    let types: HashMap<u32, &Instruction> = module
        .types_global_values
        .iter()
        .filter_map(|i| i.result_id.map(|r| (r, i)))
        .collect();
    let mut out = Reflection::default();
    for inst in &module.types_global_values {
        let Some(result) = inst.result_id else {
            continue;
        };
        match inst.class.opcode {
            Op::TypeStruct => {
                let Some(name) = names.get(&result) else {
                    continue;
                };
                let members = (0..inst.operands.len() as u32)
                    .map(|m| {
                        let member = member_names.get(&(result, m)).cloned().unwrap_or_default();
                        (
                            member,
                            offsets.get(&(result, m)).copied().unwrap_or(u32::MAX),
                        )
                    })
                    .collect();
                out.structs.insert(name.clone(), members);
            }
            Op::Variable => {
                let (Some(&set), Some(&binding)) = (sets.get(&result), bindings.get(&result))
                else {
                    continue;
                };
                let pointer = types[&inst.result_type.unwrap()];
                let (class, pointee) = match pointer.operands.as_slice() {
                    [Operand::StorageClass(c), p] => (*c, types[&id(p).unwrap()]),
                    _ => panic!("a variable's type is a pointer"),
                };
                let ty = descriptor_type(class, pointee, &types, &buffer_blocks);
                let name = names.get(&result).cloned().unwrap_or_default();
                out.bindings.insert((set, binding), (name, ty));
            }
            _ => {}
        }
    }
    out
}

fn descriptor_type(
    class: StorageClass,
    pointee: &Instruction,
    types: &HashMap<u32, &Instruction>,
    buffer_blocks: &[u32],
) -> vk::DescriptorType {
    let image = |image: &Instruction| match image.operands.as_slice() {
        [_, Operand::Dim(dim), _, _, _, sampled, ..] => (*dim, literal(sampled).unwrap()),
        _ => panic!("an image type"),
    };
    match (class, pointee.class.opcode) {
        (StorageClass::Uniform, _) if buffer_blocks.contains(&pointee.result_id.unwrap()) => {
            vk::DescriptorType::STORAGE_BUFFER
        }
        (StorageClass::Uniform, _) => vk::DescriptorType::UNIFORM_BUFFER,
        (StorageClass::StorageBuffer, _) => vk::DescriptorType::STORAGE_BUFFER,
        (_, Op::TypeSampledImage) => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
        (_, Op::TypeSampler) => vk::DescriptorType::SAMPLER,
        (_, Op::TypeImage) => match image(pointee) {
            (Dim::DimBuffer, 2) => vk::DescriptorType::STORAGE_TEXEL_BUFFER,
            (Dim::DimBuffer, _) => vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
            (_, 2) => vk::DescriptorType::STORAGE_IMAGE,
            _ => vk::DescriptorType::SAMPLED_IMAGE,
        },
        (class, op) => panic!(
            "no descriptor type for {class:?} {op:?}: {types:?}",
            types = types.len()
        ),
    }
}

/// Checks that every binding `reflection` uses exists in `sets` (`sets[set][binding]`)
/// with the same type; the message names the shader and the binding.
pub fn check_bindings(
    shader: &str,
    reflection: &Reflection,
    sets: &[&[vk::DescriptorType]],
) -> Result<(), String> {
    for (&(set, binding), (name, ty)) in &reflection.bindings {
        let declared = sets
            .get(set as usize)
            .and_then(|layout| layout.get(binding as usize));
        if declared != Some(ty) {
            return Err(format!(
                "{shader}: `{name}` at set {set}, binding {binding} is {ty:?}; the Rust layout has {declared:?}"
            ));
        }
    }
    Ok(())
}

/// Checks that the struct `name` in `reflection` has exactly `fields` (name, byte
/// offset of the Rust field), in order.
pub fn check_struct(
    shader: &str,
    reflection: &Reflection,
    name: &str,
    fields: &[(&str, usize)],
) -> Result<(), String> {
    let members = reflection
        .structs
        .get(name)
        .ok_or_else(|| format!("{shader}: no struct `{name}`"))?;
    let glsl: Vec<(&str, usize)> = members
        .iter()
        .map(|(n, o)| (n.as_str(), *o as usize))
        .collect();
    if glsl != fields {
        return Err(format!(
            "{shader}: `{name}` is laid out as {glsl:?} in GLSL, {fields:?} in Rust"
        ));
    }
    Ok(())
}

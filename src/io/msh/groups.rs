//! Gmsh physical groups: which nodes belong to each named physical point and curve.
//!
//! MSH 4.1 attaches physical tags to entities (`$Entities`) and puts each element in an
//! entity block; MSH 2.2 gives each element its physical tag directly. Either way a group's
//! nodes are the nodes of its point and line elements (gmsh saves the elements of every
//! physical group), collected while the elements are read and resolved to point indices at
//! the end. Surface and volume groups are not kept: their nodes would be the whole mesh.

use super::NodeTags;
use crate::io::lex::try_push;
use crate::io::{IoError, PhysicalGroup};
use std::collections::HashMap;

/// The element dimension of a point (15) or line (1, 8, 26, 27, 28) element type.
pub(super) fn low_dimension(element_type: usize) -> Option<u8> {
    match element_type {
        15 => Some(0),
        1 | 8 | 26 | 27 | 28 => Some(1),
        _ => None,
    }
}

#[derive(Default)]
pub(super) struct Groups {
    /// `$PhysicalNames`: (dimension, tag) -> name.
    names: HashMap<(u8, i32), String>,
    /// MSH 4.1 `$Entities`: (dimension, entity tag) -> the entity's physical tags.
    entity_physicals: HashMap<(u8, i32), Vec<i32>>,
    /// MSH 4.1: node tags of the point and line elements of each entity.
    entity_nodes: HashMap<(u8, i32), Vec<u64>>,
    /// MSH 2.2: node tags of the point and line elements of each physical group.
    physical_nodes: HashMap<(u8, i32), Vec<u64>>,
}

impl Groups {
    pub fn name(&mut self, dim: u8, tag: i32, name: String) {
        self.names.insert((dim, tag), name);
    }

    /// A 4.1 entity of dimension 0 or 1 and its physical tags (none: not recorded).
    pub fn entity(&mut self, dim: u8, tag: i32, physicals: Vec<i32>) {
        if dim <= 1 && !physicals.is_empty() {
            self.entity_physicals.insert((dim, tag), physicals);
        }
    }

    /// A 4.1 point or line element of entity (`dim`, `entity`).
    pub fn element_of_entity(&mut self, dim: u8, entity: i32, nodes: &[u64]) -> Result<(), IoError> {
        extend(self.entity_nodes.entry((dim, entity)).or_default(), nodes)
    }

    /// A 2.2 point or line element of physical group (`dim`, `physical`).
    pub fn element_of_physical(&mut self, dim: u8, physical: i32, nodes: &[u64]) -> Result<(), IoError> {
        if physical == 0 {
            return Ok(()); // no physical group
        }
        extend(self.physical_nodes.entry((dim, physical)).or_default(), nodes)
    }

    /// The groups, sorted by (dimension, tag), each with its sorted distinct point indices.
    pub fn finish(mut self, tags: &NodeTags) -> Result<Vec<PhysicalGroup>, IoError> {
        for ((dim, entity), nodes) in std::mem::take(&mut self.entity_nodes) {
            for &physical in self.entity_physicals.get(&(dim, entity)).map_or(&[][..], |p| &p[..]) {
                extend(self.physical_nodes.entry((dim, physical.abs())).or_default(), &nodes)?;
            }
        }
        // Named groups with no element (gmsh writes none for an empty group) are kept empty.
        for &(dim, tag) in self.names.keys() {
            if dim <= 1 {
                self.physical_nodes.entry((dim, tag)).or_default();
            }
        }
        let mut groups = Vec::new();
        for ((dim, tag), node_tags) in self.physical_nodes {
            let mut nodes = Vec::new();
            nodes.try_reserve_exact(node_tags.len()).map_err(|_| {
                IoError::from(crate::alloc::out_of_memory::<u32>("physical group nodes", node_tags.len()))
            })?;
            for t in node_tags {
                let index = tags.get(t).ok_or_else(|| {
                    IoError::Malformed(format!(
                        "physical group {tag} (dimension {dim}) has node {t}, which does not exist"
                    ))
                })?;
                nodes.push(index);
            }
            nodes.sort_unstable();
            nodes.dedup();
            let name = self.names.get(&(dim, tag)).cloned().unwrap_or_default();
            try_push(&mut groups, PhysicalGroup { dim, tag, name, nodes }, "physical groups")?;
        }
        groups.sort_by_key(|g| (g.dim, g.tag));
        Ok(groups)
    }
}

fn extend(v: &mut Vec<u64>, nodes: &[u64]) -> Result<(), IoError> {
    v.try_reserve(nodes.len()).map_err(|_| {
        IoError::from(crate::alloc::out_of_memory::<u64>("physical group nodes", nodes.len()))
    })?;
    v.extend_from_slice(nodes);
    Ok(())
}

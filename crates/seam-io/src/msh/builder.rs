//! Assembles an [`Msh`] from the records the section readers parse, whatever
//! the version and encoding: node tags become indices, MSH 2.2 copies of one
//! element are merged, repeated `$NodeData` names keep the last step.

use std::collections::HashMap;

use seam::Point3;

use super::element_types::ElementType;
use super::{Msh, MshElement, MshErrorKind, MshFormat, MshVersion, NodeData, PhysicalName};

/// One element as a file gives it, with node tags not yet resolved.
pub(crate) struct ElementRecord<'r> {
    pub tag: u64,
    pub element_type: ElementType,
    pub entity: i32,
    pub physical_tags: &'r [i32],
    pub node_tags: &'r [u64],
}

/// An [`Msh`] under construction.
pub(crate) struct MshBuilder {
    msh: Msh,
    index_of_tag: TagIndex,
}

/// Node tag → 0-based index. Gmsh numbers nodes 1..=n (or nearly so), so the
/// map is a table indexed by tag while the tags stay below twice the number of
/// nodes (plus a little): no hashing, and memory within a small multiple of the
/// nodes read. A larger tag moves every entry to a `HashMap` (SipHash, whose
/// cost does not depend on what tags a hostile file picks).
enum TagIndex {
    /// `table[tag]` is the index of node `tag`, or [`NO_NODE`].
    Table(Vec<usize>),
    Map(HashMap<u64, usize>),
}

const NO_NODE: usize = usize::MAX;

impl TagIndex {
    /// The largest table for `n` nodes.
    fn table_limit(n: usize) -> usize {
        n.saturating_mul(2).saturating_add(1024)
    }

    fn get(&self, tag: u64) -> Option<usize> {
        match self {
            TagIndex::Table(table) => {
                let i = usize::try_from(tag).ok()?;
                table.get(i).copied().filter(|&index| index != NO_NODE)
            }
            TagIndex::Map(map) => map.get(&tag).copied(),
        }
    }

    /// Records `tag → index` (`index` is the number of nodes before it); false
    /// if the tag is already there.
    fn insert(&mut self, tag: u64, index: usize) -> bool {
        let table = match self {
            TagIndex::Map(map) => return map.insert(tag, index).is_none(),
            TagIndex::Table(table) => table,
        };
        let limit = Self::table_limit(index + 1);
        match usize::try_from(tag) {
            Ok(i) if i < limit => {
                if i >= table.len() {
                    table.resize((i + 1).max(table.len().saturating_mul(2)).min(limit), NO_NODE);
                }
                match table.get_mut(i) {
                    Some(slot) if *slot == NO_NODE => {
                        *slot = index;
                        true
                    }
                    _ => false,
                }
            }
            _ => {
                let mut map = HashMap::with_capacity(index + 1);
                for (t, &n) in table.iter().enumerate() {
                    if n != NO_NODE {
                        map.insert(t as u64, n);
                    }
                }
                map.insert(tag, index);
                *self = TagIndex::Map(map);
                true
            }
        }
    }
}

impl MshBuilder {
    /// An empty mesh of the given format.
    pub fn new(format: MshFormat) -> Self {
        let msh = Msh::empty(format);
        MshBuilder { msh, index_of_tag: TagIndex::Table(Vec::new()) }
    }

    /// Makes room for `additional` more nodes.
    pub fn reserve_nodes(&mut self, additional: usize) {
        self.msh.nodes.reserve(additional);
        self.msh.node_tags.reserve(additional);
        let total = self.msh.nodes.len().saturating_add(additional);
        match &mut self.index_of_tag {
            // Tags 1..=n need n + 1 entries.
            TagIndex::Table(table) => table.reserve((total + 1).saturating_sub(table.len())),
            TagIndex::Map(map) => map.reserve(additional),
        }
    }

    /// Makes room for `additional` more elements.
    pub fn reserve_elements(&mut self, additional: usize) {
        self.msh.elements.reserve(additional);
    }

    /// Appends a node.
    pub fn add_node(&mut self, tag: u64, xyz: Point3) -> Result<(), MshErrorKind> {
        let index = self.msh.nodes.len();
        if !self.index_of_tag.insert(tag, index) {
            return Err(MshErrorKind::DuplicateNode { node_tag: tag });
        }
        self.msh.nodes.push(xyz);
        self.msh.node_tags.push(tag);
        Ok(())
    }

    /// The number of nodes so far.
    pub fn node_count(&self) -> usize {
        self.msh.nodes.len()
    }

    /// The 0-based index of the node with this tag.
    pub fn node_index(&self, tag: u64) -> Option<usize> {
        self.index_of_tag.get(tag)
    }

    /// Appends an element, resolving its node tags (the nodes must come first,
    /// as `$Nodes` precedes `$Elements`).
    pub fn add_element(&mut self, record: ElementRecord<'_>) -> Result<(), MshErrorKind> {
        let mut nodes = Vec::with_capacity(record.node_tags.len());
        for &node_tag in record.node_tags {
            let index = self.node_index(node_tag);
            nodes.push(index.ok_or(MshErrorKind::UnknownNode { element_tag: record.tag, node_tag })?);
        }
        let element = MshElement {
            tag: record.tag,
            gmsh_type: record.element_type.number,
            dim: record.element_type.dim(),
            entity: record.entity,
            nodes,
            physical_tags: record.physical_tags.to_vec(),
        };
        if !self.merge_into_previous(&element) {
            self.msh.elements.push(element);
        }
        Ok(())
    }

    /// MSH 2.2 writes an element once per physical group: if `element` repeats
    /// the previous one but for its physical tag, adds the tag there instead.
    fn merge_into_previous(&mut self, element: &MshElement) -> bool {
        if self.msh.format.version != MshVersion::V2_2 {
            return false;
        }
        let Some(previous) = self.msh.elements.last_mut() else {
            return false;
        };
        let same = previous.gmsh_type == element.gmsh_type
            && previous.entity == element.entity
            && previous.nodes == element.nodes;
        if same {
            for &tag in &element.physical_tags {
                if !previous.physical_tags.contains(&tag) {
                    previous.physical_tags.push(tag);
                }
            }
        }
        same
    }

    /// Appends a `$PhysicalNames` entry.
    pub fn add_physical_name(&mut self, name: PhysicalName) {
        self.msh.physical_names.push(name);
    }

    /// Adds a `$NodeData` field, replacing an earlier one of the same name.
    pub fn add_node_data(&mut self, data: NodeData) {
        match self.msh.node_data.iter_mut().find(|d| d.name == data.name) {
            Some(earlier) => *earlier = data,
            None => self.msh.node_data.push(data),
        }
    }

    /// The finished mesh.
    pub fn finish(self) -> Msh {
        self.msh
    }
}

#[cfg(test)]
mod tests {
    use super::super::element_types::element_type;
    use super::*;

    fn record<'r>(tag: u64, physical_tags: &'r [i32], node_tags: &'r [u64]) -> ElementRecord<'r> {
        ElementRecord { tag, element_type: element_type(2).unwrap(), entity: 1, physical_tags, node_tags }
    }

    fn builder(version: MshVersion) -> MshBuilder {
        let mut b = MshBuilder::new(MshFormat { version, binary: false });
        for (tag, x) in [(10, 0.0), (20, 1.0), (30, 2.0)] {
            b.add_node(tag, [x, x * x, 0.0]).unwrap();
        }
        b
    }

    #[test]
    fn node_tags_become_indices_in_file_order() {
        let mut b = builder(MshVersion::V4_1);
        b.add_element(record(5, &[7], &[30, 10, 20])).unwrap();
        let msh = b.finish();
        assert_eq!(msh.elements[0].nodes, vec![2, 0, 1]);
        assert_eq!(msh.elements[0].dim, 2);
    }

    #[test]
    fn unknown_and_duplicate_tags_are_errors() {
        let mut b = builder(MshVersion::V4_1);
        let e = b.add_element(record(5, &[], &[10, 20, 40])).unwrap_err();
        assert!(matches!(e, MshErrorKind::UnknownNode { element_tag: 5, node_tag: 40 }));
        let e = b.add_node(20, [0.0; 3]).unwrap_err();
        assert!(matches!(e, MshErrorKind::DuplicateNode { node_tag: 20 }));
    }

    #[test]
    fn sparse_tags_move_the_index_to_a_map() {
        let mut b = MshBuilder::new(MshFormat { version: MshVersion::V4_1, binary: false });
        for (i, tag) in [5u64, 3, 1 << 40, 7, u64::MAX].into_iter().enumerate() {
            b.add_node(tag, [i as f64; 3]).unwrap();
        }
        let found: Vec<_> = [5u64, 3, 1 << 40, 7, u64::MAX, 4, 0].map(|t| b.node_index(t)).into();
        assert_eq!(found, [Some(0), Some(1), Some(2), Some(3), Some(4), None, None]);
        assert!(matches!(b.add_node(1 << 40, [0.0; 3]), Err(MshErrorKind::DuplicateNode { .. })));
        assert!(matches!(b.add_node(3, [0.0; 3]), Err(MshErrorKind::DuplicateNode { .. })));
        let mut b = MshBuilder::new(MshFormat { version: MshVersion::V4_1, binary: false });
        b.add_node(0, [0.0; 3]).unwrap();
        assert!(matches!(b.add_node(0, [0.0; 3]), Err(MshErrorKind::DuplicateNode { node_tag: 0 })));
        assert_eq!(b.node_index(1), None);
    }

    #[test]
    fn msh2_copies_of_an_element_merge_their_physical_tags() {
        let mut b = builder(MshVersion::V2_2);
        b.add_element(record(1, &[7], &[10, 20, 30])).unwrap();
        b.add_element(record(2, &[8], &[10, 20, 30])).unwrap();
        b.add_element(record(3, &[7], &[30, 20, 10])).unwrap();
        let msh = b.finish();
        assert_eq!(msh.elements.len(), 2);
        assert_eq!(msh.elements[0].tag, 1);
        assert_eq!(msh.elements[0].physical_tags, vec![7, 8]);
    }

    #[test]
    fn the_last_node_data_of_a_name_wins() {
        let mut b = builder(MshVersion::V4_1);
        let data =
            |step: i32| NodeData { name: "u".into(), time_step: step, components: 1, values: vec![0.0; 3] };
        b.add_node_data(data(0));
        b.add_node_data(data(1));
        let msh = b.finish();
        assert_eq!(msh.node_data.len(), 1);
        assert_eq!(msh.node_data[0].time_step, 1);
    }
}

//! From the definitions of a model to an [`Msh`]: instances placed and
//! numbered, node ids resolved, solids in Gmsh's node order, element sets as
//! volume groups and surfaces as face elements in surface groups.

use std::collections::HashMap;

use crate::msh::{Msh, MshElement, MshFormat, MshVersion, PhysicalName, UnusableGroup};

use super::input::Sources;
use super::read::{Entry, Item, Model, Scope, SetDef, SurfaceDef, SurfaceType, MAX_ID};
use super::types::{local_face, n_faces, SUPPORTED};
use super::{face_tag, InpError, Loc};

/// The instances and the top level, as they become parts of the mesh.
struct Unit<'m> {
    /// `Some(name)` for an instance, whose names are qualified `name.`.
    instance: Option<&'m str>,
    /// The part's definitions, then the instance's own (or the top level's).
    scopes: Vec<&'m Scope>,
    translation: [f64; 3],
    /// Added to every node and element id.
    offset: u64,
    nodes: HashMap<u64, usize>,
    elements: HashMap<u64, Element>,
}

/// An element of a unit: a cell of the mesh (index into its elements) or one
/// of a type seam skips (index into [`Model::types`]).
#[derive(Clone, Copy)]
enum Element {
    Cell(usize),
    Skipped { ty: usize, at: Loc },
}

/// A set resolved: its cells, or why it cannot be used.
struct Resolved {
    cells: Vec<usize>,
    problem: Option<String>,
}

/// Builds the mesh.
pub(super) fn build(model: &Model, sources: &Sources) -> Result<Msh, InpError> {
    let mut units: Vec<Unit> = model
        .instances
        .iter()
        .map(|i| Unit {
            instance: Some(&i.name),
            scopes: vec![&model.parts[i.part].scope, &i.own],
            translation: i.translation,
            offset: 0,
            nodes: HashMap::new(),
            elements: HashMap::new(),
        })
        .collect();
    units.push(Unit {
        instance: None,
        scopes: vec![&model.top],
        translation: [0.0; 3],
        offset: 0,
        nodes: HashMap::new(),
        elements: HashMap::new(),
    });
    number_units(&mut units, model, sources)?;
    let mut builder = Builder {
        model,
        sources,
        msh: Msh::empty(MshFormat { version: MshVersion::AbaqusInp, binary: false }),
        cell_types: Vec::new(),
        memberships: 0,
    };
    for u in 0..units.len() {
        builder.nodes(&mut units[u])?;
        builder.cells(&mut units[u], u)?;
    }
    let mut sets: HashMap<String, Resolved> = HashMap::new();
    let mut next_tag = 1;
    for unit in &units {
        for set in unit.scopes.iter().flat_map(|s| &s.sets) {
            let name = qualified(unit.instance, &set.name);
            let resolved = builder.resolve_set(set, unit, &units, &sets)?;
            builder.add_set_group(&name, next_tag, &resolved);
            next_tag += 1;
            sets.insert(name.to_ascii_uppercase(), resolved);
        }
    }
    let mut faces: HashMap<(usize, usize), usize> = HashMap::new();
    let mut face_elements = Vec::new();
    for unit in &units {
        for surface in unit.scopes.iter().flat_map(|s| &s.surfaces) {
            let name = qualified(unit.instance, &surface.name);
            builder.msh.physical_names.push(PhysicalName { dim: 2, tag: next_tag, name });
            let selected = builder.surface_faces(surface, unit, &units, &sets)?;
            match selected {
                Ok(list) => {
                    for (cell, face) in list {
                        let index = *faces.entry((cell, face)).or_insert_with(|| {
                            face_elements.push(builder.face_element(cell, face));
                            face_elements.len() - 1
                        });
                        let tags: &mut Vec<i32> = &mut face_elements[index].physical_tags;
                        if !tags.contains(&next_tag) {
                            tags.push(next_tag);
                        }
                    }
                }
                Err(reason) => {
                    builder.msh.unusable_groups.push(UnusableGroup { dim: 2, tag: next_tag, reason })
                }
            }
            next_tag += 1;
        }
    }
    builder.msh.elements.extend(face_elements);
    Ok(builder.msh)
}

/// `instance.name`, or `name` at the top level.
fn qualified(instance: Option<&str>, name: &str) -> String {
    match instance {
        Some(instance) => format!("{instance}.{name}"),
        None => name.to_string(),
    }
}

/// Gives the units their id offsets: none if one unit has nodes or elements;
/// otherwise the `j`-th such unit (instances in file order, then the top
/// level) adds `j·10^k`, `10^k` the smallest power of ten above every id.
/// Refuses instances that repeat their parts beyond the input's size.
fn number_units(units: &mut [Unit], model: &Model, sources: &Sources) -> Result<(), InpError> {
    let size = |u: &Unit| u.scopes.iter().map(|s| s.nodes.len() + s.elements.len()).sum::<usize>();
    let repeated: usize = model
        .instances
        .iter()
        .map(|i| {
            let part = &model.parts[i.part].scope;
            part.nodes.len() + part.elements.len() + part.sets.iter().map(|s| s.entries.len()).sum::<usize>()
        })
        .sum();
    if repeated > sources.bytes {
        return Err(InpError::new(format!(
            "the instances repeat {repeated} nodes, elements and set entries of their parts, more than the input's {} \
             bytes: seam reads at most one per byte",
            sources.bytes
        )).at(sources.files[0].clone(), 0));
    }
    let max_id = units
        .iter()
        .flat_map(|u| u.scopes.iter())
        .flat_map(|s| s.nodes.iter().map(|n| n.id).chain(s.elements.iter().map(|e| e.id)))
        .max()
        .unwrap_or(0);
    let mut base = 10u64;
    while base <= max_id {
        base *= 10;
    }
    let limit = MAX_ID * 10_000;
    for (j, unit) in units.iter_mut().filter(|u| size(u) > 0).enumerate() {
        unit.offset =
            (j as u64).checked_mul(base).filter(|o| o.saturating_add(base) <= limit).ok_or_else(|| {
                InpError::new(format!("too many instances: ids with their offsets go beyond {limit}"))
                    .at(sources.files[0].clone(), 0)
            })?;
    }
    Ok(())
}

struct Builder<'a> {
    model: &'a Model,
    sources: &'a Sources,
    msh: Msh,
    /// The type (index into [`Model::types`]) of each cell.
    cell_types: Vec<usize>,
    /// Set and surface memberships so far, bounded by the input's size.
    memberships: usize,
}

impl Builder<'_> {
    /// " of part P (instance I)" or "" at the top level, for messages.
    fn whose(unit: &Unit) -> String {
        unit.instance.map_or(String::new(), |i| format!(" in instance {i}"))
    }

    fn nodes(&mut self, unit: &mut Unit) -> Result<(), InpError> {
        for node in unit.scopes.iter().flat_map(|s| &s.nodes) {
            let index = self.msh.nodes.len();
            if let Some(&first) = unit.nodes.get(&node.id) {
                let earlier = self.msh.node_tags[first];
                return Err(self.sources.error(
                    node.at,
                    format!(
                        "node {} is defined twice{} (node {earlier} of the mesh)",
                        node.id,
                        Self::whose(unit)
                    ),
                ));
            }
            unit.nodes.insert(node.id, index);
            let xyz = std::array::from_fn(|c| node.xyz[c] + unit.translation[c]);
            if xyz.iter().any(|x: &f64| !x.is_finite()) {
                return Err(self
                    .sources
                    .error(node.at, format!("node {} is translated out of range", node.id)));
            }
            self.msh.nodes.push(xyz);
            self.msh.node_tags.push(node.id + unit.offset);
        }
        Ok(())
    }

    fn cells(&mut self, unit: &mut Unit, u: usize) -> Result<(), InpError> {
        for scope in &unit.scopes {
            for element in &scope.elements {
                let ty = &self.model.types[element.ty];
                let entry = match &ty.solid {
                    None => Element::Skipped { ty: element.ty, at: element.at },
                    Some(solid) => {
                        let n = solid.kind.n_nodes();
                        let mut nodes = vec![0; n];
                        for (i, &id) in scope.node_ids[element.first..element.first + n].iter().enumerate() {
                            let Some(&index) = unit.nodes.get(&id) else {
                                return Err(self.sources.error(
                                    element.at,
                                    format!(
                                        "element {} refers to node {id}, which is not defined{}",
                                        element.id,
                                        Self::whose(unit)
                                    ),
                                ));
                            };
                            nodes[solid.gmsh_position[i]] = index;
                        }
                        self.msh.elements.push(MshElement {
                            tag: element.id + unit.offset,
                            gmsh_type: solid.kind.info().gmsh_type.unwrap_or(0),
                            dim: 3,
                            entity: i32::try_from(u + 1).unwrap_or(i32::MAX),
                            nodes,
                            physical_tags: Vec::new(),
                        });
                        self.cell_types.push(element.ty);
                        Element::Cell(self.msh.elements.len() - 1)
                    }
                };
                if unit.elements.insert(element.id, entry).is_some() {
                    return Err(self.sources.error(
                        element.at,
                        format!("element {} is defined twice{}", element.id, Self::whose(unit)),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The unit an entry's ids refer to, and the rest of a qualified name:
    /// `Part-1-1.Set-1` → (that instance, `Set-1`).
    fn target<'u>(
        &self,
        entry: &Entry,
        name: Option<&'u str>,
        unit: &'u Unit<'u>,
        units: &'u [Unit<'u>],
    ) -> (&'u Unit<'u>, Option<&'u str>) {
        if let Some(i) = entry.instance {
            return (&units[i], name);
        }
        if let Some((prefix, rest)) = name.and_then(|n| n.split_once('.')) {
            if let Some(u) = units.iter().find(|u| u.instance.is_some_and(|i| i.eq_ignore_ascii_case(prefix)))
            {
                return (u, Some(rest));
            }
        }
        (unit, name)
    }

    /// Why element `id` of `unit` cannot be in a set or surface, or its cell.
    fn cell(&self, unit: &Unit, id: u64, at: Loc) -> Result<usize, String> {
        match unit.elements.get(&id) {
            Some(Element::Cell(c)) => Ok(*c),
            Some(Element::Skipped { ty, at }) => Err(format!(
                "element {id}{} ({}) is of type {}, not a solid seam reads ({SUPPORTED})",
                Builder::whose(unit),
                self.sources.describe(*at),
                self.model.types[*ty].name
            )),
            None => Err(format!(
                "element {id}{} ({}) is not defined",
                Builder::whose(unit),
                self.sources.describe(at)
            )),
        }
    }

    /// The cells of one set entry, or why it cannot be used.
    fn entry_cells(
        &self,
        entry: &Entry,
        unit: &Unit,
        units: &[Unit],
        sets: &HashMap<String, Resolved>,
        out: &mut Vec<usize>,
    ) -> Result<(), String> {
        match &entry.item {
            &Item::Id(id) => out.push(self.cell(self.target(entry, None, unit, units).0, id, entry.at)?),
            &Item::Range(first, last, step) => {
                let (unit, _) = self.target(entry, None, unit, units);
                // Ids a range names that are no elements are left out.
                for id in (first..=last).step_by(usize::try_from(step).unwrap_or(usize::MAX)) {
                    if unit.elements.contains_key(&id) {
                        out.push(self.cell(unit, id, entry.at)?);
                    }
                }
            }
            Item::Name(name) => {
                let (unit, rest) = self.target(entry, Some(name), unit, units);
                let rest = rest.unwrap_or(name);
                if let Ok(id) = rest.parse::<u64>() {
                    out.push(self.cell(unit, id, entry.at)?);
                    return Ok(());
                }
                let key = qualified(unit.instance, rest).to_ascii_uppercase();
                match sets.get(&key) {
                    Some(Resolved { problem: Some(problem), .. }) => {
                        return Err(format!("its set {name} cannot be used: {problem}"))
                    }
                    Some(set) => out.extend_from_slice(&set.cells),
                    None => {
                        return Err(format!(
                            "{} names set {name}, which is not defined before it",
                            self.sources.describe(entry.at)
                        ))
                    }
                }
            }
        }
        Ok(())
    }

    fn resolve_set(
        &mut self,
        set: &SetDef,
        unit: &Unit,
        units: &[Unit],
        sets: &HashMap<String, Resolved>,
    ) -> Result<Resolved, InpError> {
        let mut cells = Vec::new();
        for entry in &set.entries {
            if let Err(problem) = self.entry_cells(entry, unit, units, sets, &mut cells) {
                return Ok(Resolved { cells: Vec::new(), problem: Some(problem) });
            }
        }
        cells.sort_unstable();
        cells.dedup();
        self.count(cells.len(), set.at)?;
        Ok(Resolved { cells, problem: None })
    }

    /// Counts `n` more memberships, refusing more than the input's size
    /// allows (sets of sets of sets…).
    fn count(&mut self, n: usize, at: Loc) -> Result<(), InpError> {
        self.memberships = self.memberships.saturating_add(n);
        let limit = self.sources.bytes.saturating_mul(4).saturating_add(1 << 20);
        if self.memberships > limit {
            return Err(self.sources.error(
                at,
                format!(
                    "the sets and surfaces hold more than {limit} elements in all, 4 per byte of the input"
                ),
            ));
        }
        Ok(())
    }

    fn add_set_group(&mut self, name: &str, tag: i32, set: &Resolved) {
        self.msh.physical_names.push(PhysicalName { dim: 3, tag, name: name.to_string() });
        match &set.problem {
            Some(problem) => {
                let reason = format!("element set {name}: {problem}");
                self.msh.unusable_groups.push(UnusableGroup { dim: 3, tag, reason });
            }
            None => {
                for &c in &set.cells {
                    self.msh.elements[c].physical_tags.push(tag);
                }
            }
        }
    }

    /// The (cell, face) pairs of a surface, or why it cannot be used.
    fn surface_faces(
        &mut self,
        surface: &SurfaceDef,
        unit: &Unit,
        units: &[Unit],
        sets: &HashMap<String, Resolved>,
    ) -> Result<Result<Vec<(usize, usize)>, String>, InpError> {
        let at = self.sources.describe(surface.at);
        match &surface.ty {
            SurfaceType::Element => {}
            SurfaceType::Node => {
                return Ok(Err(format!(
                "*SURFACE {} ({at}) is TYPE=NODE, a set of nodes: seam couples element faces, defined with \
                     TYPE=ELEMENT and the labels S1…S6",
                surface.name
            )))
            }
            SurfaceType::Other(ty) => {
                return Ok(Err(format!(
                    "*SURFACE {} ({at}) is {ty}: seam reads TYPE=ELEMENT surfaces only",
                    surface.name
                )))
            }
        }
        let mut faces = Vec::new();
        for (entry, label) in &surface.entries {
            let line = self.sources.describe(entry.at);
            let Some(label) = label else {
                return Ok(Err(format!(
                    "{line} gives no face label: seam needs one of S1…S6 for each element or set"
                )));
            };
            let face = label
                .strip_prefix(['S', 's'])
                .and_then(|k| k.parse::<usize>().ok())
                .filter(|k| (1..=6).contains(k));
            let mut cells = Vec::new();
            if let Err(problem) = self.entry_cells(entry, unit, units, sets, &mut cells) {
                return Ok(Err(problem));
            }
            for cell in cells {
                let ty = &self.model.types[self.cell_types[cell]];
                let kind = ty.solid.as_ref().map(|s| s.kind).expect("cells are solids");
                match face.filter(|&k| k <= n_faces(kind)) {
                    Some(k) => faces.push((cell, k)),
                    None => {
                        return Ok(Err(format!(
                            "{line}: element {} of type {} has faces S1…S{}, not {label}",
                            self.msh.elements[cell].tag,
                            ty.name,
                            n_faces(kind)
                        )))
                    }
                }
            }
        }
        self.count(faces.len(), surface.at)?;
        Ok(Ok(faces))
    }

    /// The face element of face `S{face}` of cell `cell`.
    fn face_element(&self, cell: usize, face: usize) -> MshElement {
        let element = &self.msh.elements[cell];
        let kind = self.model.types[self.cell_types[cell]].solid.as_ref().map(|s| s.kind).expect("a solid");
        let local =
            local_face(kind, face).expect("every face S1…Sn of a cell kind is one of its local faces");
        face_element(element, local, face as u8)
    }
}

/// The face element of local face `local`, numbered `face`, of cell
/// `element`: tag [`face_tag`], the cell's entity, no groups yet.
pub(crate) fn face_element(element: &MshElement, local: &seam::LocalFace, face: u8) -> MshElement {
    MshElement {
        tag: face_tag(element.tag, face),
        gmsh_type: local.kind.info().gmsh_type.unwrap_or(0),
        dim: 2,
        entity: element.entity,
        nodes: local.nodes().iter().map(|&l| element.nodes[l]).collect(),
        physical_tags: Vec::new(),
    }
}

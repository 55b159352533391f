//! From keyword and data lines to the definitions of a model: parts,
//! instances and the top level, each with its nodes, elements, element sets
//! and surfaces, ids not yet resolved.

use std::collections::HashMap;

use super::input::{shorten, split_fields, Keyword, Line, Sources};
use super::types::{solid_type, SolidType};
use super::{InpError, Loc};

/// The largest node or element id read (Abaqus allows 999 999 999): face
/// tags and instance offsets stay below 10¹⁷.
pub(super) const MAX_ID: u64 = 1_000_000_000_000;

/// An element type as the file names it.
pub(super) struct TypeDef {
    /// The name in upper case.
    pub name: String,
    /// The solid type, if seam reads it.
    pub solid: Option<SolidType>,
}

/// A node.
pub(super) struct NodeDef {
    pub id: u64,
    pub xyz: [f64; 3],
    pub at: Loc,
}

/// An element; the node ids of a solid are `Scope::node_ids[first..first + n]`.
pub(super) struct ElementDef {
    pub id: u64,
    /// Index into [`Model::types`].
    pub ty: usize,
    pub first: usize,
    pub at: Loc,
}

/// What a set or surface line refers to.
pub(super) enum Item {
    /// An element id.
    Id(u64),
    /// `first, last, step` of a `GENERATE` line.
    Range(u64, u64, u64),
    /// A set name, maybe instance-qualified (`Part-1-1.Set-1`), or an
    /// instance-qualified element id (`Part-1-1.12`).
    Name(String),
}

/// One entry of a set.
pub(super) struct Entry {
    pub item: Item,
    /// The instance of an assembly-level `*ELSET, INSTANCE=…` (index into
    /// [`Model::instances`]).
    pub instance: Option<usize>,
    pub at: Loc,
}

/// An element set (all `*ELSET`s and `ELSET=`s of one name in one scope).
pub(super) struct SetDef {
    /// The name as first written.
    pub name: String,
    pub entries: Vec<Entry>,
    pub at: Loc,
}

/// The `TYPE=` of a `*SURFACE`.
pub(super) enum SurfaceType {
    Element,
    Node,
    /// Anything else, as written (`CUTTING SURFACE`, `COMBINE=UNION`, …).
    Other(String),
}

/// A `*SURFACE`.
pub(super) struct SurfaceDef {
    pub name: String,
    pub ty: SurfaceType,
    /// The element or set, and the face label as written (if any).
    pub entries: Vec<(Entry, Option<String>)>,
    pub at: Loc,
}

/// The definitions of a part, an instance or the top level (the assembly
/// included).
#[derive(Default)]
pub(super) struct Scope {
    pub nodes: Vec<NodeDef>,
    pub elements: Vec<ElementDef>,
    pub node_ids: Vec<u64>,
    pub sets: Vec<SetDef>,
    set_index: HashMap<String, usize>,
    pub surfaces: Vec<SurfaceDef>,
    surface_index: HashMap<String, usize>,
}

impl Scope {
    /// The set named `name` (any case), created at `at` if new.
    fn set(&mut self, name: &str, at: Loc) -> usize {
        let sets = &mut self.sets;
        *self.set_index.entry(name.to_ascii_uppercase()).or_insert_with(|| {
            sets.push(SetDef { name: name.to_string(), entries: Vec::new(), at });
            sets.len() - 1
        })
    }

    /// The surface named `name` (any case), created if new.
    fn surface(&mut self, name: &str, ty: SurfaceType, at: Loc) -> usize {
        let surfaces = &mut self.surfaces;
        *self.surface_index.entry(name.to_ascii_uppercase()).or_insert_with(|| {
            surfaces.push(SurfaceDef { name: name.to_string(), ty, entries: Vec::new(), at });
            surfaces.len() - 1
        })
    }
}

/// A `*PART`.
pub(super) struct Part {
    pub name: String,
    pub scope: Scope,
}

/// An `*INSTANCE` of a part, translated, with the definitions inside it
/// (Abaqus/CAE writes independent instances' meshes there).
pub(super) struct Instance {
    pub name: String,
    /// Index into [`Model::parts`].
    pub part: usize,
    pub translation: [f64; 3],
    pub own: Scope,
}

/// Everything read.
#[derive(Default)]
pub(super) struct Model {
    pub types: Vec<TypeDef>,
    pub parts: Vec<Part>,
    pub instances: Vec<Instance>,
    pub top: Scope,
}

/// Where definitions go.
#[derive(Clone, Copy, PartialEq)]
enum Place {
    Top,
    Part(usize),
    Instance(usize),
}

/// What the data lines under the current keyword are.
enum Block {
    Skip,
    Node,
    Element(ElementBlock),
    Elset {
        set: usize,
        generate: bool,
        instance: Option<usize>,
    },
    Surface {
        surface: usize,
        instance: Option<usize>,
    },
    /// Translation (line 0) and rotation (line 1) of an instance.
    Instance {
        instance: usize,
        lines: usize,
    },
}

/// The state of an `*ELEMENT` block: the type, the set, and the element
/// whose data lines are being read.
struct ElementBlock {
    ty: usize,
    /// The node count of a solid type; `None` for types seam skips, whose
    /// data lines end unless they end with a comma.
    nodes: Option<usize>,
    set: Option<usize>,
    values: Vec<u64>,
    start: Loc,
}

/// Reads every line of `sources` into a model.
pub(super) fn read_model(sources: &mut Sources) -> Result<Model, InpError> {
    let mut reader =
        Reader { model: Model::default(), place: Place::Top, block: Block::Skip, type_index: HashMap::new() };
    while let Some(line) = sources.next()? {
        match line {
            Line::Keyword(keyword) => {
                reader.end_block(sources)?;
                reader.keyword(&keyword, sources)?;
            }
            Line::Data(text, at) => reader.data(&text, at, sources)?,
        }
    }
    reader.end_block(sources)?;
    Ok(reader.model)
}

struct Reader {
    model: Model,
    place: Place,
    block: Block,
    type_index: HashMap<String, usize>,
}

impl Reader {
    fn scope(&mut self) -> &mut Scope {
        match self.place {
            Place::Top => &mut self.model.top,
            Place::Part(p) => &mut self.model.parts[p].scope,
            Place::Instance(i) => &mut self.model.instances[i].own,
        }
    }

    /// Finishes the element whose data lines were being read, if any.
    fn end_block(&mut self, sources: &Sources) -> Result<(), InpError> {
        let block = std::mem::replace(&mut self.block, Block::Skip);
        if let Block::Element(mut element) = block {
            if !element.values.is_empty() {
                if let Some(n) = element.nodes {
                    let name = &self.model.types[element.ty].name;
                    return Err(sources.error(
                        element.start,
                        format!(
                            "element {} of type {name} has {n} nodes, but its data end after {}",
                            element.values[0],
                            element.values.len() - 1
                        ),
                    ));
                }
                self.finish_element(&mut element);
            }
        }
        Ok(())
    }

    fn keyword(&mut self, k: &Keyword, sources: &Sources) -> Result<(), InpError> {
        let at = k.at;
        let required = |option: &str| {
            k.option(option)
                .filter(|v| !v.is_empty())
                .ok_or_else(|| sources.error(at, format!("*{} without {option}=", k.name)))
        };
        self.block = match k.name.as_str() {
            "NODE" => {
                refuse_input(k, sources)?;
                if let Some(system) = k.option("SYSTEM").filter(|s| !s.eq_ignore_ascii_case("R")) {
                    return Err(sources.error(
                        at,
                        format!(
                            "*NODE, SYSTEM={system}: only rectangular coordinates (SYSTEM=R) are supported"
                        ),
                    ));
                }
                Block::Node
            }
            "ELEMENT" => {
                refuse_input(k, sources)?;
                let name = required("TYPE")?.to_ascii_uppercase();
                let ty = match self.type_index.get(&name) {
                    Some(&ty) => ty,
                    None => {
                        let solid = solid_type(&name);
                        self.model.types.push(TypeDef { name: name.clone(), solid });
                        self.type_index.insert(name, self.model.types.len() - 1);
                        self.model.types.len() - 1
                    }
                };
                let nodes = self.model.types[ty].solid.as_ref().map(|s| s.kind.n_nodes());
                let set = k.option("ELSET").filter(|s| !s.is_empty()).map(|s| self.scope().set(s, at));
                Block::Element(ElementBlock { ty, nodes, set, values: Vec::new(), start: at })
            }
            "ELSET" => {
                let name = required("ELSET")?;
                let instance = self.instance_option(k, sources)?;
                let set = self.scope().set(name, at);
                Block::Elset { set, generate: k.flag("GENERATE"), instance }
            }
            "SURFACE" => {
                let name = required("NAME")?;
                let ty = match k.option("TYPE").map(str::to_ascii_uppercase).as_deref() {
                    _ if k.flag("COMBINE") => SurfaceType::Other("COMBINE".into()),
                    None | Some("ELEMENT") => SurfaceType::Element,
                    Some("NODE") => SurfaceType::Node,
                    Some(other) => SurfaceType::Other(other.to_string()),
                };
                let surface = self.scope().surface(name, ty, at);
                Block::Surface { surface, instance: None }
            }
            "PART" => {
                if self.place != Place::Top {
                    return Err(sources.error(at, "*PART inside a *PART or *INSTANCE (missing *END PART?)"));
                }
                let name = required("NAME")?.to_string();
                self.model.parts.push(Part { name, scope: Scope::default() });
                self.place = Place::Part(self.model.parts.len() - 1);
                Block::Skip
            }
            "INSTANCE" => {
                if self.place != Place::Top {
                    return Err(sources.error(at, "*INSTANCE inside a *PART or *INSTANCE (missing *END …?)"));
                }
                let name = required("NAME")?.to_string();
                let part_name = required("PART")?;
                let Some(part) = self.model.parts.iter().position(|p| p.name.eq_ignore_ascii_case(part_name))
                else {
                    return Err(
                        sources.error(at, format!("*INSTANCE {name}: no *PART {part_name} before it"))
                    );
                };
                if self.find_instance(&name).is_some() {
                    return Err(sources.error(at, format!("*INSTANCE {name} is defined twice")));
                }
                let instance = Instance { name, part, translation: [0.0; 3], own: Scope::default() };
                self.model.instances.push(instance);
                self.place = Place::Instance(self.model.instances.len() - 1);
                Block::Instance { instance: self.model.instances.len() - 1, lines: 0 }
            }
            "ENDPART" | "ENDINSTANCE" | "ASSEMBLY" | "ENDASSEMBLY" => {
                self.place = Place::Top;
                Block::Skip
            }
            _ => Block::Skip,
        };
        Ok(())
    }

    /// The instance named by an `INSTANCE=` option (assembly-level sets).
    fn instance_option(&self, k: &Keyword, sources: &Sources) -> Result<Option<usize>, InpError> {
        match k.option("INSTANCE").filter(|v| !v.is_empty()) {
            None => Ok(None),
            Some(name) => match self.find_instance(name) {
                Some(i) => Ok(Some(i)),
                None => Err(sources.error(k.at, format!("*{}: no *INSTANCE {name} before it", k.name))),
            },
        }
    }

    fn find_instance(&self, name: &str) -> Option<usize> {
        self.model.instances.iter().position(|i| i.name.eq_ignore_ascii_case(name))
    }

    fn data(&mut self, text: &str, at: Loc, sources: &Sources) -> Result<(), InpError> {
        let fields = split_fields(text);
        match &mut self.block {
            Block::Skip => Ok(()),
            Block::Node => {
                let id = parse_id(fields[0], "a node number", sources, at)?;
                let mut xyz = [0.0; 3];
                for (c, (x, field)) in xyz.iter_mut().zip(fields.iter().skip(1)).enumerate() {
                    *x = parse_real(field, sources, at, || format!("coordinate {} of node {id}", c + 1))?;
                }
                self.scope().nodes.push(NodeDef { id, xyz, at });
                Ok(())
            }
            Block::Element(element) => {
                if element.values.is_empty() {
                    element.start = at;
                }
                let continued = text.ends_with(',');
                let used = if continued { &fields[..fields.len() - 1] } else { &fields[..] };
                for field in used {
                    let what = if element.values.is_empty() { "an element number" } else { "a node number" };
                    element.values.push(parse_id(field, what, sources, at)?);
                }
                let done = match element.nodes {
                    Some(n) if element.values.len() > n + 1 => {
                        let name = &self.model.types[element.ty].name;
                        return Err(sources.error(
                            element.start,
                            format!(
                                "element {} of type {name} has {n} nodes, but its data list {}",
                                element.values[0],
                                element.values.len() - 1
                            ),
                        ));
                    }
                    Some(n) => element.values.len() == n + 1,
                    None => !continued,
                };
                if done {
                    let mut element = match std::mem::replace(&mut self.block, Block::Skip) {
                        Block::Element(e) => e,
                        _ => unreachable!("the block is an element block"),
                    };
                    self.finish_element(&mut element);
                    self.block = Block::Element(element);
                }
                Ok(())
            }
            &mut Block::Elset { set, generate, instance } => {
                let items = fields.iter().filter(|f| !f.is_empty());
                let mut entries = Vec::new();
                if generate {
                    entries.push(Entry { item: parse_range(&fields, sources, at)?, instance, at });
                } else {
                    for field in items {
                        entries.push(Entry { item: parse_item(field, sources, at)?, instance, at });
                    }
                }
                self.scope().sets[set].entries.extend(entries);
                Ok(())
            }
            &mut Block::Surface { surface, instance } => {
                let item = parse_item(fields[0], sources, at)?;
                let label = fields.get(1).filter(|l| !l.is_empty()).map(|l| l.to_string());
                self.scope().surfaces[surface].entries.push((Entry { item, instance, at }, label));
                Ok(())
            }
            Block::Instance { instance, lines } => {
                let (instance, line) = (*instance, *lines);
                *lines += 1;
                let name = &self.model.instances[instance].name;
                let numbers = fields
                    .iter()
                    .enumerate()
                    .map(|(i, f)| {
                        parse_real(f, sources, at, || format!("value {} of instance {name}", i + 1))
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                match line {
                    0 => {
                        let t = &mut self.model.instances[instance].translation;
                        for (t, x) in t.iter_mut().zip(&numbers) {
                            *t = *x;
                        }
                        Ok(())
                    }
                    1 if numbers.get(6).is_none_or(|&angle| angle == 0.0) => Ok(()),
                    1 => Err(sources.error(
                        at,
                        format!("*INSTANCE {name} is rotated: rotated instances are not supported (rotate the part's nodes instead)"),
                    )),
                    _ => Err(sources.error(
                        at,
                        format!("*INSTANCE {name} has more than two data lines (translation, rotation): {:?}", shorten(text)),
                    )),
                }
            }
        }
    }

    /// Stores the element whose values (id, then nodes for a solid) were
    /// read, and empties them.
    fn finish_element(&mut self, element: &mut ElementBlock) {
        let values = std::mem::take(&mut element.values);
        let (ty, set, at) = (element.ty, element.set, element.start);
        let solid = self.model.types[ty].solid.is_some();
        let scope = self.scope();
        let first = scope.node_ids.len();
        if solid {
            scope.node_ids.extend_from_slice(&values[1..]);
        }
        scope.elements.push(ElementDef { id: values[0], ty, first, at });
        if let Some(set) = set {
            scope.sets[set].entries.push(Entry { item: Item::Id(values[0]), instance: None, at });
        }
    }
}

/// `*NODE, INPUT=…` and `*ELEMENT, INPUT=…` read their data from another
/// file: not supported.
fn refuse_input(k: &Keyword, sources: &Sources) -> Result<(), InpError> {
    match k.option("INPUT") {
        Some(file) => Err(sources.error(
            k.at,
            format!("*{}, INPUT={file}: data in another file is not supported (use *INCLUDE)", k.name),
        )),
        None => Ok(()),
    }
}

/// A node or element number: a whole number up to [`MAX_ID`] (CalculiX's
/// examples have a node 0).
fn parse_id(field: &str, what: &str, sources: &Sources, at: Loc) -> Result<u64, InpError> {
    match field.parse::<u64>() {
        Ok(id) if id <= MAX_ID => Ok(id),
        Ok(id) => Err(sources.error(at, format!("{what} must be at most {MAX_ID}, found {id}"))),
        Err(_) => Err(sources.error(at, format!("expected {what}, found {:?}", shorten(field)))),
    }
}

/// A real number as Abaqus writes them (`1.`, `.5`, `1.5E+3`, `1.5D3`);
/// empty is 0.
fn parse_real(field: &str, sources: &Sources, at: Loc, what: impl Fn() -> String) -> Result<f64, InpError> {
    if field.is_empty() {
        return Ok(0.0);
    }
    let plain = field.bytes().all(|b| b.is_ascii_digit() || b"+-.eEdD".contains(&b));
    let value = if plain { field.replace(['d', 'D'], "e").parse::<f64>().ok() } else { None };
    match value {
        Some(x) if x.is_finite() => Ok(x),
        Some(_) => Err(sources.error(at, format!("{} is {field}, out of range", what()))),
        None => {
            Err(sources.error(at, format!("expected a number for {}, found {:?}", what(), shorten(field))))
        }
    }
}

/// An element id or a (maybe qualified) set name.
fn parse_item(field: &str, sources: &Sources, at: Loc) -> Result<Item, InpError> {
    if field.is_empty() {
        return Err(sources.error(at, "an empty element or set name"));
    }
    match field.bytes().all(|b| b.is_ascii_digit()) {
        true => Ok(Item::Id(parse_id(field, "an element number", sources, at)?)),
        false => Ok(Item::Name(field.trim_matches('"').to_string())),
    }
}

/// `first, last[, step]` of a `GENERATE` line; its count is bounded by the
/// input's size, so that the set's memory is.
fn parse_range(fields: &[&str], sources: &Sources, at: Loc) -> Result<Item, InpError> {
    let fields: Vec<&str> = fields.iter().copied().filter(|f| !f.is_empty()).collect();
    if !(2..=3).contains(&fields.len()) {
        return Err(sources
            .error(at, format!("a GENERATE line is first, last[, step]; found {} values", fields.len())));
    }
    let first = parse_id(fields[0], "the first element number", sources, at)?;
    let last = parse_id(fields[1], "the last element number", sources, at)?;
    let step = match fields.get(2) {
        Some(step) => parse_id(step, "a step", sources, at)?,
        None => 1,
    };
    if step == 0 {
        return Err(sources.error(at, "a GENERATE step must be at least 1"));
    }
    if last < first {
        return Err(
            sources.error(at, format!("GENERATE from {first} down to {last}: the last number is smaller"))
        );
    }
    let count = (last - first) / step + 1;
    if count > sources.bytes as u64 {
        return Err(sources.error(
            at,
            format!(
                "GENERATE from {first} to {last} by {step} names {count} elements, more than the input's {} bytes \
                 can define",
                sources.bytes
            ),
        ));
    }
    Ok(Item::Range(first, last, step))
}

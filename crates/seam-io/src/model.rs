//! One entry point for the model files seam reads as an [`Msh`]: Gmsh MSH
//! files, Abaqus / CalculiX input files and Exodus II files, chosen by extension or by name
//! ([`read_model_file`]).

use std::fmt;
use std::path::Path;

use crate::msh::{read_msh, Msh, MshError, MshErrorKind};

/// The format of a model file (a mesh with named groups of cells and faces).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelFormat {
    /// Gmsh MSH, 4.1 or 2.2 ([`crate::read_msh`]).
    Gmsh,
    /// Abaqus or CalculiX input ([`crate::read_inp_file`]).
    Abaqus,
    /// Exodus II ([`crate::read_exodus_file`]; needs the `exodus` feature).
    Exodus,
}

impl ModelFormat {
    /// Every format, in the order of [`ModelFormat::NAMES`].
    pub const ALL: [ModelFormat; 3] = [ModelFormat::Gmsh, ModelFormat::Abaqus, ModelFormat::Exodus];

    /// The names [`ModelFormat::from_name`] accepts: `"gmsh"`, `"abaqus"`,
    /// `"exodus"`.
    pub const NAMES: [&'static str; 3] = ["gmsh", "abaqus", "exodus"];

    /// The format of a file by its extension (in any case): `.inp` is
    /// Abaqus; `.e`, `.exo`, `.ex2` and `.g` are Exodus II; anything else
    /// Gmsh.
    pub fn of_path(path: &Path) -> ModelFormat {
        let is = |x: &str| path.extension().is_some_and(|e| e.eq_ignore_ascii_case(x));
        if is("inp") {
            ModelFormat::Abaqus
        } else if ["e", "exo", "ex2", "g"].into_iter().any(is) {
            ModelFormat::Exodus
        } else {
            ModelFormat::Gmsh
        }
    }

    /// The format called `name` (one of [`ModelFormat::NAMES`], exactly).
    pub fn from_name(name: &str) -> Option<ModelFormat> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }

    /// Its name: `"gmsh"`, `"abaqus"` or `"exodus"`.
    pub fn name(self) -> &'static str {
        match self {
            ModelFormat::Gmsh => Self::NAMES[0],
            ModelFormat::Abaqus => Self::NAMES[1],
            ModelFormat::Exodus => Self::NAMES[2],
        }
    }
}

impl fmt::Display for ModelFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Reads a model file as an [`Msh`]: as `format`, or when `None` by the
/// extension ([`ModelFormat::of_path`]: `.inp` is an Abaqus input file,
/// `.e`, `.exo`, `.ex2` and `.g` Exodus II, anything else Gmsh MSH).
///
/// # Errors
/// An [`MshError`] naming the file: I/O errors (see [`MshError::io_kind`]) as
/// [`crate::read_msh_file`] gives them for either format, MSH errors as
/// [`crate::read_msh_file`], `.inp` errors as [`MshErrorKind::Abaqus`]
/// (`part.inp:12: cause`), Exodus errors as [`MshErrorKind::Exodus`]
/// (`body.exo: element block 2: cause`).
pub fn read_model_file(path: impl AsRef<Path>, format: Option<ModelFormat>) -> Result<Msh, MshError> {
    let path = path.as_ref();
    let bytes =
        crate::read_regular_file(path).map_err(|e| MshError::new(MshErrorKind::Io(e)).with_path(path))?;
    match format.unwrap_or_else(|| ModelFormat::of_path(path)) {
        ModelFormat::Gmsh => read_msh(&bytes).map_err(|e| e.with_path(path)),
        ModelFormat::Abaqus => Ok(crate::abaqus::read_inp_read_from(bytes, path)?),
        ModelFormat::Exodus => Ok(crate::exodus::read_exodus_read_from(&bytes, path)?),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_by_extension_and_name() {
        assert_eq!(ModelFormat::of_path(Path::new("a/part.INP")), ModelFormat::Abaqus);
        assert_eq!(ModelFormat::of_path(Path::new("part.inp")), ModelFormat::Abaqus);
        assert_eq!(ModelFormat::of_path(Path::new("part.msh")), ModelFormat::Gmsh);
        assert_eq!(ModelFormat::of_path(Path::new("inp")), ModelFormat::Gmsh);
        for name in ["a.e", "a.EXO", "b/a.ex2", "a.g"] {
            assert_eq!(ModelFormat::of_path(Path::new(name)), ModelFormat::Exodus);
        }
        assert_eq!(ModelFormat::of_path(Path::new("a.exodus")), ModelFormat::Gmsh);
        for f in ModelFormat::ALL {
            assert_eq!(ModelFormat::from_name(f.name()), Some(f));
        }
        assert_eq!(ModelFormat::from_name("vtu"), None);
    }
}

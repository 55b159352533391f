//! Reading a surface with its point fields from a Gmsh MSH file ($NodeData) or
//! a VTU file (point data), and evaluating an expression at its points.

use anyhow::{anyhow, bail, Context, Result};
use exmex::prelude::*;
use seam::{Point3, SurfaceMesh};
use seam_io::Field;
use std::path::Path;

/// A surface mesh and the nodal fields its file carries.
pub struct Surface {
    pub mesh: SurfaceMesh,
    pub fields: Vec<Field>,
}

impl Surface {
    /// Reads `path`: `.vtu` as VTU (point data), anything else as Gmsh MSH
    /// ($NodeData; `group` selects a physical surface).
    pub fn read(path: &Path, group: Option<&str>) -> Result<Surface> {
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("vtu")) {
            if let Some(g) = group {
                bail!(
                    "{}: physical groups exist in MSH files only, but --*-group {g} was given",
                    path.display()
                );
            }
            let vtu = seam_io::read_vtu_file(path)?;
            return Ok(Surface { mesh: vtu.mesh, fields: vtu.point_data });
        }
        let msh = seam_io::read_msh_file(path)?;
        let mesh = msh.surface(group).map_err(|e| e.with_path(path))?;
        let fields = msh
            .node_data
            .iter()
            .map(|d| Field::new(d.name.clone(), d.components, d.values.clone()))
            .collect();
        Ok(Surface { mesh, fields })
    }

    /// The field `name`, checked to be finite at every point of the surface.
    pub fn field(&self, name: &str, path: &Path) -> Result<&Field> {
        let field = self.fields.iter().find(|f| f.name == name).ok_or_else(|| {
            let known: Vec<&str> = self.fields.iter().map(|f| f.name.as_str()).collect();
            let known = if known.is_empty() { "none".to_string() } else { known.join(", ") };
            anyhow!("{}: no field named '{name}' (fields: {known})", path.display())
        })?;
        let k = field.components;
        if field.values.len() != self.mesh.n_points() * k {
            bail!(
                "{}: field '{name}' has {} values, but {} points × {k} components were expected",
                path.display(),
                field.values.len(),
                self.mesh.n_points()
            );
        }
        let used = self.mesh.used_points();
        if let Some(p) = (0..used.len())
            .find(|&p| used[p] && field.values[p * k..(p + 1) * k].iter().any(|v| !v.is_finite()))
        {
            bail!(
                "{}: field '{name}' has no finite value at node {} (the {}-th node of the file)",
                path.display(),
                p + 1,
                p + 1
            );
        }
        Ok(field)
    }
}

/// An expression in x, y, z, parsed once.
pub struct Expression {
    expr: FlatEx<f64>,
    /// For each variable of the expression (alphabetical, as exmex orders
    /// them), the coordinate it stands for.
    axes: Vec<usize>,
}

impl Expression {
    /// Parses `text`; its variables must be among x, y, z.
    pub fn parse(text: &str) -> Result<Expression> {
        let expr =
            exmex::parse::<f64>(text).map_err(|e| anyhow!("the expression '{text}' does not parse: {e}"))?;
        let axes = expr
            .var_names()
            .iter()
            .map(|v| match v.as_str() {
                "x" => Ok(0),
                "y" => Ok(1),
                "z" => Ok(2),
                other => Err(anyhow!("the expression '{text}' uses '{other}'; only x, y and z are known")),
            })
            .collect::<Result<Vec<usize>>>()?;
        Ok(Expression { expr, axes })
    }

    /// The value at `p`.
    pub fn at(&self, p: Point3) -> Result<f64> {
        let args: Vec<f64> = self.axes.iter().map(|&k| p[k]).collect();
        self.expr.eval(&args).context("evaluating the expression")
    }

    /// The values at all points of `mesh`.
    pub fn sample(&self, mesh: &SurfaceMesh) -> Result<Vec<f64>> {
        mesh.points().iter().map(|&p| self.at(p)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expressions_take_x_y_z_in_any_order_and_subset() {
        let e = Expression::parse("sin(x)*y + z").unwrap();
        assert!((e.at([0.5, 2.0, -1.0]).unwrap() - (0.5f64.sin() * 2.0 - 1.0)).abs() < 1e-15);
        let e = Expression::parse("z - y").unwrap();
        assert_eq!(e.at([9.0, 2.0, 5.0]).unwrap(), 3.0);
        assert_eq!(Expression::parse("2.5").unwrap().at([1.0, 1.0, 1.0]).unwrap(), 2.5);
        assert!(Expression::parse("sin(x").is_err());
        let err = Expression::parse("x + w").err().unwrap().to_string();
        assert!(err.contains("'w'"), "{err}");
    }
}

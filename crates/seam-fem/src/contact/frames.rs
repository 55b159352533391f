//! The contact points and their unknowns: per covered slave point its nodal
//! frame (n, t₁, t₂), weighted gap and constraint row ([`ContactPoint`]), the
//! rotation of its dofs into the frame, and the change of variables to the
//! transformed slave basis on second-order faces ([`SlaveBasis`]; module doc
//! of [`crate::contact`]).

use crate::constraints::{triple_product, Constraints, NONE};
use crate::multibody::{Body, Coupling, Interface, ProblemError, System};
use crate::solve::Dirichlet;
use seam::vec3::{cross, dot, norm, sub};
use seam::{nodal_normals, CsrMatrix, Mortar, Point3};

/// A contact point: slave point `point` of interface `interface`, its dofs
/// `first_dof` … + 2 (x, y, z in the global numbering), reinterpreted as
/// (w, v₁, v₂).
#[derive(Clone, Debug)]
pub(crate) struct ContactPoint {
    pub(super) interface: usize,
    pub(super) point: usize,
    pub(super) first_dof: usize,
    /// n, t₁, t₂.
    pub(super) frame: [Point3; 3],
    /// d_p.
    pub(super) d: f64,
    /// g_p.
    pub(super) gap: f64,
    /// (global master dof of component 0, T_pq).
    pub(super) t_row: Vec<(usize, f64)>,
    /// n_p·(T u_m)_p = Σ a_j y_j in the unknowns y left after the glued
    /// interfaces' elimination, u = P_g y: (j, a_j).
    pub(super) a_row: Vec<(usize, f64)>,
}

/// The change of variables u = P_b ũ on the slave points of the contact
/// interfaces whose mortar has a basis transformation Q (dual multipliers on
/// second-order slave faces, module doc): u_s = Qᵀ ũ_s per component there,
/// the identity elsewhere.
pub(super) struct SlaveBasis {
    /// P_b, n × n.
    pub(super) p: CsrMatrix,
    /// The Dirichlet conditions in ũ.
    pub(super) dirichlet: Dirichlet,
}

impl SlaveBasis {
    /// None when no contact interface has a basis transformation.
    ///
    /// # Errors
    /// [`ProblemError::BadInterface`] for a point transformed by two
    /// interfaces, or a prescribed component that does not carry over to ũ
    /// (an edge node's, with a corner of its edge free in that component).
    pub(super) fn new(
        bodies: &[Body],
        interfaces: &[Interface],
        system: &System,
    ) -> Result<Option<SlaveBasis>, ProblemError> {
        let n = *system.offsets.last().expect("at least the leading zero");
        let mut rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n / 3];
        let mut owner = vec![NONE; n / 3];
        let contact = interfaces
            .iter()
            .zip(&system.mortars)
            .enumerate()
            .filter(|(_, (f, _))| f.kind == Coupling::Contact);
        let mut any = false;
        for (i, (f, m)) in contact {
            let Some(q) = &m.basis else { continue };
            any = true;
            let base = system.offsets[f.slave] / 3;
            let qt = q.transpose();
            for r in (0..qt.nrows).filter(|&r| m.on_surface[r]) {
                let (cols, vals) = qt.row(r);
                if cols == [r] && vals == [1.0] {
                    continue;
                }
                if owner[base + r] != NONE {
                    let at = bodies[f.slave].mesh.points()[r];
                    let what = format!(
                        "slave point {r} at ({}, {}, {}) is on the second-order slave faces of contact interfaces {} and {i}: \
                         their dual bases cannot share a point (split the surfaces)",
                        at[0], at[1], at[2], owner[base + r]
                    );
                    return Err(ProblemError::BadInterface { interface: i, what });
                }
                owner[base + r] = i;
                rows[base + r] = cols.iter().zip(vals).map(|(&p, &v)| (base + p, v)).collect();
            }
        }
        if !any {
            return Ok(None);
        }
        let contact = interfaces.iter().enumerate().filter(|(_, f)| f.kind == Coupling::Contact);
        for (i, f) in contact {
            let base = system.offsets[f.master] / 3;
            let used = f.master_surface.used_points();
            if let Some(q) = (0..used.len()).find(|&q| used[q] && owner[base + q] != NONE) {
                let at = bodies[f.master].mesh.points()[q];
                let what = format!(
                    "master point {q} at ({}, {}, {}) is on the second-order slave faces of contact interface {}: \
                     a contact master surface cannot share points with a transformed slave surface",
                    at[0], at[1], at[2], owner[base + q]
                );
                return Err(ProblemError::BadInterface { interface: i, what });
            }
        }
        let dirichlet = Self::transformed_dirichlet(bodies, system, &rows, &owner)?;
        let mut p = CsrMatrix::zeros(0, n);
        for dof in 0..n {
            let (point, comp) = (dof / 3, dof % 3);
            if rows[point].is_empty() {
                p.indices.push(dof);
                p.values.push(1.0);
            } else {
                let mut row: Vec<(usize, f64)> =
                    rows[point].iter().map(|&(q, a)| (3 * q + comp, a)).collect();
                row.sort_unstable_by_key(|e| e.0);
                p.indices.extend(row.iter().map(|e| e.0));
                p.values.extend(row.iter().map(|e| e.1));
            }
            p.indptr.push(p.indices.len());
            p.nrows += 1;
        }
        Ok(Some(SlaveBasis { p, dirichlet }))
    }

    /// The prescribed values in ũ: u_r,k = Σ_q a_q ũ_q,k prescribed at a
    /// corner (u_c = ũ_c) carries over; at an edge node, when both corners
    /// of its edge have component k prescribed too, ũ_e,k = (u_e,k − Σ_c a_c
    /// u_c,k) / a_e. Anything else is refused.
    pub(super) fn transformed_dirichlet(
        bodies: &[Body],
        system: &System,
        rows: &[Vec<(usize, f64)>],
        owner: &[usize],
    ) -> Result<Dirichlet, ProblemError> {
        let dirichlet = &system.dirichlet;
        let mut out = Dirichlet::new();
        for (dof, v) in dirichlet.iter() {
            let (point, comp) = (dof / 3, dof % 3);
            let row = &rows[point];
            if row.is_empty() {
                out.fix_dof(dof, v);
                continue;
            }
            let mut value = v;
            let mut own = 1.0;
            for &(q, a) in row {
                if q == point {
                    own = a;
                    continue;
                }
                // q is a corner: u_q = ũ_q.
                match dirichlet.value(3 * q + comp).filter(|_| rows[q].iter().all(|&(c, _)| c == q)) {
                    Some(uq) => value -= a * uq / rows[q].first().map_or(1.0, |e| e.1),
                    None => {
                        let body = system.offsets.partition_point(|&o| o <= dof) - 1;
                        let local = point - system.offsets[body] / 3;
                        let corner = q - system.offsets[body] / 3;
                        let at = bodies[body].mesh.points()[local];
                        let what = format!(
                            "slave point {local} at ({}, {}, {}) has component {comp} prescribed, but point {corner}, a \
                             corner of its edge, does not: with second-order slave faces the contact unknowns \
                             mix an edge node with its corners (Popp et al. 2012), so a prescribed component must \
                             be prescribed on the whole edge",
                            at[0], at[1], at[2]
                        );
                        return Err(ProblemError::BadInterface { interface: owner[point], what });
                    }
                }
            }
            out.fix_dof(dof, value / own);
        }
        Ok(out)
    }

    /// `system` and `constraints` in ũ (module doc of [`crate::contact`]):
    /// K̃ = P_bᵀ K P_b (K moved out of `system`: not needed after the solve),
    /// f̃ = P_bᵀ f, the Dirichlet conditions in ũ and C̃ = C P_b; `system`'s
    /// mortars and points move to the result (the caller moves them back).
    pub(super) fn transform(&self, system: &mut System, constraints: &Constraints) -> (System, Constraints) {
        let transformed = System {
            k: triple_product(&self.p, &std::mem::replace(&mut system.k, CsrMatrix::zeros(0, 0))),
            f: self.p.transpose_mul_vec(&system.f, 1),
            dirichlet: self.dirichlet.clone(),
            offsets: system.offsets.clone(),
            mortars: std::mem::take(&mut system.mortars),
            points: std::mem::take(&mut system.points),
        };
        let mut glued = constraints.clone();
        glued.c = self.times(&constraints.c);
        (transformed, glued)
    }

    /// C P_b for a matrix C with n columns.
    pub(super) fn times(&self, c: &CsrMatrix) -> CsrMatrix {
        let mut out = CsrMatrix::zeros(0, c.ncols);
        let mut row: Vec<(usize, f64)> = Vec::new();
        for i in 0..c.nrows {
            row.clear();
            let (cols, vals) = c.row(i);
            for (&j, &v) in cols.iter().zip(vals) {
                let (pc, pv) = self.p.row(j);
                row.extend(pc.iter().zip(pv).map(|(&k, &a)| (k, v * a)));
            }
            for (j, v) in merged(&mut row) {
                out.indices.push(j);
                out.values.push(v);
            }
            out.indptr.push(out.indices.len());
            out.nrows += 1;
        }
        out
    }
}

/// The contact points of all interfaces, in interface and point order: covered
/// slave points not claimed by an earlier interface whose normal is not
/// prescribed.
pub(super) fn contact_points(
    bodies: &[Body],
    interfaces: &[Interface],
    mortars: &[Mortar],
    offsets: &[usize],
    dirichlet: &Dirichlet,
    p_g: Option<&CsrMatrix>,
) -> Result<Vec<ContactPoint>, ProblemError> {
    let n = *offsets.last().unwrap();
    let mut claimed = vec![false; n / 3];
    let mut points = Vec::new();
    let contact =
        interfaces.iter().zip(mortars).enumerate().filter(|(_, (f, _))| f.kind == Coupling::Contact);
    for (i, (f, m)) in contact {
        let (os, om) = (offsets[f.slave], offsets[f.master]);
        let normals = nodal_normals(f.slave_surface);
        let (xs, xm) = (bodies[f.slave].mesh.points(), bodies[f.master].mesh.points());
        // The slave positions in the transformed basis, x̃_s = Q⁻ᵀ x_s = D⁻¹ (D Q⁻ᵀ) x_s.
        let nodal_d = m.basis.as_ref().map(|_| m.nodal_d());
        let position = |p: usize, d: f64| -> Point3 {
            match &nodal_d {
                None => xs[p],
                Some(n) => {
                    let (cols, vals) = n.row(p);
                    std::array::from_fn(|c| cols.iter().zip(vals).map(|(&r, &v)| v / d * xs[r][c]).sum())
                }
            }
        };
        for p in (0..m.covered.len()).filter(|&p| m.covered[p]) {
            let first_dof = os + 3 * p;
            if claimed[first_dof / 3] {
                continue;
            }
            let fixed: [bool; 3] = std::array::from_fn(|c| dirichlet.value(first_dof + c).is_some());
            let Some(frame) = frame(normals[p], fixed) else { continue };
            claimed[first_dof / 3] = true;
            let d = m.d.get(p, p);
            let (cols, vals) = m.b.row(p);
            let t_row: Vec<(usize, f64)> =
                cols.iter().zip(vals).map(|(&q, &b)| (om + 3 * q, b / d)).collect();
            let txm: Point3 =
                std::array::from_fn(|c| cols.iter().zip(vals).map(|(&q, &b)| b / d * xm[q][c]).sum());
            let gap = dot(frame[0], sub(txm, position(p, d)));
            let a_row = normal_row(&t_row, frame[0], p_g);
            points.push(ContactPoint { interface: i, point: p, first_dof, frame, d, gap, t_row, a_row });
        }
    }
    let slave_point: Vec<bool> = {
        let mut s = vec![false; n / 3];
        points.iter().for_each(|c| s[c.first_dof / 3] = true);
        s
    };
    for c in &points {
        if let Some(&(q, _)) = c.t_row.iter().find(|(q, _)| slave_point[q / 3]) {
            let what = format!(
                "master point {} is also a contact point of another interface; chains of contact \
                 through one point are not supported",
                (q - offsets[interfaces[c.interface].master]) / 3
            );
            return Err(ProblemError::BadInterface { interface: c.interface, what });
        }
    }
    Ok(points)
}

/// n·(T u_m)_p in the unknowns y, u = P_g y: the entries (q + k, T_pq n_k) of
/// `t_row`, each expanded through its row of P_g when a glued interface
/// eliminates it.
pub(super) fn normal_row(t_row: &[(usize, f64)], n: Point3, p_g: Option<&CsrMatrix>) -> Vec<(usize, f64)> {
    let mut row = Vec::new();
    for &(q, t) in t_row {
        for k in 0..3 {
            let a = t * n[k];
            match p_g {
                None => row.push((q + k, a)),
                Some(p) => {
                    let (cols, vals) = p.row(q + k);
                    row.extend(cols.iter().zip(vals).map(|(&j, &v)| (j, a * v)));
                }
            }
        }
    }
    merged(&mut row)
}

/// The entries of `row` sorted by index, those with equal indices summed.
pub(crate) fn merged(row: &mut [(usize, f64)]) -> Vec<(usize, f64)> {
    row.sort_by_key(|e| e.0);
    let mut merged: Vec<(usize, f64)> = Vec::with_capacity(row.len());
    for &(j, v) in row.iter() {
        match merged.last_mut() {
            Some(last) if last.0 == j => last.1 += v,
            _ => merged.push((j, v)),
        }
    }
    merged
}

/// The nodal frame (n, t₁, t₂): n the normal with its prescribed components
/// removed, t₁, t₂ an orthonormal basis of n⊥ containing the prescribed axes.
/// None when the normal is (nearly) prescribed: the point cannot move along it.
pub(crate) fn frame(normal: Point3, fixed: [bool; 3]) -> Option<[Point3; 3]> {
    let mut n = normal;
    for c in (0..3).filter(|&c| fixed[c]) {
        n[c] = 0.0;
    }
    let length = norm(n);
    if length < 0.5 || length.is_nan() {
        return None;
    }
    n = n.map(|v| v / length);
    let axis = |c: usize| std::array::from_fn(|i| if i == c { 1.0 } else { 0.0 });
    // t₁: a prescribed axis if any, else the axis most orthogonal to n, made orthogonal.
    let t1 = match (0..3).find(|&c| fixed[c]) {
        Some(c) => axis(c),
        None => {
            let c = (0..3).min_by(|&i, &j| n[i].abs().total_cmp(&n[j].abs())).unwrap();
            let e: Point3 = axis(c);
            let t = sub(e, n.map(|v| v * n[c]));
            let l = norm(t);
            t.map(|v| v / l)
        }
    };
    Some([n, t1, cross(n, t1)])
}

/// Per mesh point of the n dofs: the index of its contact point, or `NONE`.
pub(super) fn point_index(n: usize, points: &[ContactPoint]) -> Vec<usize> {
    let mut at = vec![NONE; n / 3];
    for (i, c) in points.iter().enumerate() {
        at[c.first_dof / 3] = i;
    }
    at
}

/// P (n × n): the identity except at contact points, whose rows read
/// u_s,p = n (w + Σ_q T_pq n·u_m,q) + t₁ v₁ + t₂ v₂ (module doc); with
/// `relative` (per point, per tangent) the marked tangents are relative
/// too, u_s,p = … + t_k (v_k + Σ_q T_pq t_k·u_m,q), so that v_k is the
/// tangential jump t_k·(u_s − T u_m)_p (frictional contact), T u_m through
/// `p_g` where glued interfaces are eliminated (as `a_row`).
pub(super) fn rotation(
    n: usize,
    points: &[ContactPoint],
    relative: Option<&[[bool; 2]]>,
    p_g: Option<&CsrMatrix>,
) -> CsrMatrix {
    let at = point_index(n, points);
    let mut p = CsrMatrix::zeros(0, n);
    let mut row: Vec<(usize, f64)> = Vec::new();
    for dof in 0..n {
        row.clear();
        match at[dof / 3] {
            NONE => row.push((dof, 1.0)),
            i => {
                let c = &points[i];
                let comp = dof % 3;
                let [nn, t1, t2] = c.frame;
                row.extend([
                    (c.first_dof, nn[comp]),
                    (c.first_dof + 1, t1[comp]),
                    (c.first_dof + 2, t2[comp]),
                ]);
                // Zeros stay: whole 3 × 3 blocks keep the point graph for the ordering.
                row.extend(c.a_row.iter().map(|&(j, a)| (j, nn[comp] * a)));
                for k in (1..3).filter(|&k| relative.is_some_and(|r| r[i][k - 1])) {
                    let e = c.frame[k];
                    row.extend(normal_row(&c.t_row, e, p_g).into_iter().map(|(j, a)| (j, e[comp] * a)));
                }
                row = merged(&mut row);
            }
        }
        p.indices.extend(row.iter().map(|e| e.0));
        p.values.extend(row.iter().map(|e| e.1));
        p.indptr.push(p.indices.len());
        p.nrows += 1;
    }
    p
}

/// The Dirichlet conditions in x: unchanged off the contact points; at a
/// contact point a prescribed axis is ±t₁ or ±t₂ (see [`frame`]), so the
/// value, with that sign, moves to v₁ or v₂.
pub(super) fn rotated_dirichlet(n: usize, dirichlet: &Dirichlet, points: &[ContactPoint]) -> Dirichlet {
    let at = point_index(n, points);
    let mut out = Dirichlet::new();
    for (dof, v) in dirichlet.iter() {
        match at[dof / 3] {
            NONE => out.fix_dof(dof, v),
            i => {
                let c = &points[i];
                let axis = dof % 3;
                let k =
                    (1..3).find(|&k| c.frame[k][axis].abs() == 1.0).expect("prescribed axes are tangents");
                // t_k = ±e_axis (t₂ = n × t₁ may point along −e_axis).
                out.fix_dof(c.first_dof + k, v * c.frame[k][axis])
            }
        };
    }
    out
}

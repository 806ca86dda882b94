//! Global matrices of the complex-coordinate system (Eq. 12–14, A8):
//! `M ü + (C − jΩG) u̇ + (K − P(t)·S) u = Q e^{jΩt}`.
//!
//! `M, C, K, S, G` are real symmetric and independent of speed; they are built once and
//! the speed enters only through [`SystemMatrices::damping_at`].

use crate::model::{element, CircuitState, Model, RingSupport, Section};
use faer::{c64, Mat};
use serde::Serialize;

/// What a global DOF is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DofKind {
    /// Complex shaft deflection u = v + jw at a node (m).
    Deflection,
    /// Complex slope θ = ∂u/∂x at a node (rad).
    Slope,
    /// Complex ring displacement a (m).
    Ring,
    /// Generalised charge q̃ of a shunt branch (C·m/C = m, Eq. A3).
    Charge,
}

/// Layout of the global DOF vector: shaft nodes `[u, θ]`, then per ring in the model's
/// order the ring DOF followed by its branch charges.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DofMap {
    /// Number of shaft nodes.
    pub nodes: usize,
    /// Charge DOFs of each ring, in ring order (its N branches when closed, 0 otherwise).
    pub branches: Vec<usize>,
}

impl DofMap {
    /// The layout of a model's DOFs.
    pub fn of(model: &Model) -> DofMap {
        DofMap { nodes: model.shaft.nodes(), branches: model.rings.iter().map(|r| r.circuit.charge_dofs()).collect() }
    }
    /// Total number of complex DOFs.
    pub fn len(&self) -> usize {
        2 * self.nodes + self.branches.iter().map(|b| 1 + b).sum::<usize>()
    }
    /// Always false: a model has at least one element.
    pub fn is_empty(&self) -> bool {
        false
    }
    /// Shaft DOFs 2(n+1).
    pub fn shaft_dofs(&self) -> usize {
        2 * self.nodes
    }
    /// Number of rings.
    pub fn rings(&self) -> usize {
        self.branches.len()
    }
    /// Charge DOFs of all rings.
    pub fn charges(&self) -> usize {
        self.branches.iter().sum()
    }
    /// Deflection DOF of a node.
    pub fn deflection(&self, node: usize) -> usize {
        2 * node
    }
    /// Slope DOF of a node.
    pub fn slope(&self, node: usize) -> usize {
        2 * node + 1
    }
    /// Ring DOF of ring `ring` (0-based, model order).
    pub fn ring(&self, ring: usize) -> usize {
        self.shaft_dofs() + self.branches[..ring].iter().map(|b| 1 + b).sum::<usize>()
    }
    /// Charge DOF of branch `i` of ring `ring`.
    pub fn charge(&self, ring: usize, i: usize) -> usize {
        self.ring(ring) + 1 + i
    }
    /// The kind of every DOF, in order.
    pub fn kinds(&self) -> Vec<DofKind> {
        let mut v = Vec::with_capacity(self.len());
        for _ in 0..self.nodes {
            v.push(DofKind::Deflection);
            v.push(DofKind::Slope);
        }
        for &b in &self.branches {
            v.push(DofKind::Ring);
            v.extend(std::iter::repeat_n(DofKind::Charge, b));
        }
        v
    }
}

/// The speed-independent global matrices and the unbalance amplitude.
#[derive(Debug, Clone)]
pub struct SystemMatrices {
    /// DOF layout: which row is which node, ring or charge.
    pub dofs: DofMap,
    /// Mass M (kg, and γL for charges).
    pub m: Mat<f64>,
    /// Viscous damping C (η at the rings, γR for charges).
    pub c: Mat<f64>,
    /// Stiffness K (bending, ring springs, Eq. A8 coupling).
    pub k: Mat<f64>,
    /// Geometric stiffness S per unit axial load (1/m).
    pub s: Mat<f64>,
    /// Gyroscopic matrix per unit speed G (kg·m²); enters as −jΩG.
    pub g: Mat<f64>,
    /// Unbalance per unit Ω²: m·e·e^{jγ} at each disk's deflection DOF (kg·m), so that
    /// the force of Eq. (12)–(14) is Q(t) = Ω²·unbalance·e^{jΩt} (N).
    pub unbalance: Vec<c64>,
}

fn add_element(target: &mut Mat<f64>, first: usize, e: &element::ElementMatrix) {
    for (i, row) in e.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            target[(first + i, first + j)] += v;
        }
    }
}

/// The elements of a Timoshenko or tapered section (or layer) from their own geometry,
/// into `[M, K, S, G]` from element `first_element` on (a uniform section's are all
/// alike, computed once).
fn add_beams(targets: &mut [&mut Mat<f64>; 4], dofs: &DofMap, first_element: usize, section: &Section) {
    let uniform = section.is_uniform().then(|| element::beam(&section.element(0)));
    for local in 0..section.elements {
        let b = uniform.unwrap_or_else(|| element::beam(&section.element(local)));
        let first = dofs.deflection(first_element + local);
        for (target, e) in targets.iter_mut().zip([&b.mass, &b.stiffness, &b.geometric, &b.gyroscopic]) {
            add_element(target, first, e);
        }
    }
}

fn add_spring(target: &mut Mat<f64>, a: usize, b: usize, k: f64) {
    target[(a, a)] += k;
    target[(b, b)] += k;
    target[(a, b)] -= k;
    target[(b, a)] -= k;
}

impl SystemMatrices {
    /// Assemble the model (Eq. 12 in complex form, Eq. 14): the element matrices of each
    /// section, the disks, the plain bearings, then the rings in model order.
    pub fn assemble(model: &Model) -> SystemMatrices {
        SystemMatrices::assemble_with(model, true)
    }

    /// [`SystemMatrices::assemble`] with the bearings' and seals' stiffness and damping
    /// (`supports`) or without (their masses always): the isotropic part of a model whose
    /// supports the real coordinates carry ([`GeneralSystem`]).
    pub fn assemble_with(model: &Model, supports: bool) -> SystemMatrices {
        let dofs = DofMap::of(model);
        let n = dofs.len();
        let mut m = Mat::<f64>::zeros(n, n);
        let mut c = Mat::<f64>::zeros(n, n);
        let mut k = Mat::<f64>::zeros(n, n);
        let mut s = Mat::<f64>::zeros(n, n);
        let mut g = Mat::<f64>::zeros(n, n);

        let mut first_element = 0;
        for section in &model.shaft.sections {
            if section.is_uniform_rayleigh() {
                // The paper's closed forms, in the order they always were added (bits).
                let (l, rho, a, i) = (section.element_length(), section.density, section.area(), section.inertia());
                let me = element::translational_mass(rho, a, l);
                let mr = element::rotary_mass(rho, i, l);
                let ke = element::bending_stiffness(section.youngs_modulus, i, l);
                let se = element::geometric(l);
                let ge = element::gyroscopic(rho, i, l);
                for e in first_element..first_element + section.elements {
                    let first = dofs.deflection(e);
                    add_element(&mut m, first, &me);
                    add_element(&mut m, first, &mr);
                    add_element(&mut k, first, &ke);
                    add_element(&mut s, first, &se);
                    add_element(&mut g, first, &ge);
                }
            } else {
                add_beams(&mut [&mut m, &mut k, &mut s, &mut g], &dofs, first_element, section);
            }
            // Concentric layers over the same nodes add their own elements.
            for layer in &section.layers {
                add_beams(&mut [&mut m, &mut k, &mut s, &mut g], &dofs, first_element, layer);
            }
            first_element += section.elements;
        }

        let mut unbalance = vec![c64::new(0.0, 0.0); n];
        for d in &model.disks {
            let (u, t) = (dofs.deflection(d.node), dofs.slope(d.node));
            m[(u, u)] += d.mass;
            m[(t, t)] += d.diametral_inertia;
            g[(t, t)] += d.polar_inertia;
            unbalance[u] += c64::from_polar(d.mass * d.eccentricity, d.phase);
        }

        for b in &model.bearings {
            let u = dofs.deflection(b.node);
            m[(u, u)] += b.mass;
            if supports {
                c[(u, u)] += b.damping();
                k[(u, u)] += b.stiffness();
            }
        }

        for (index, support) in model.rings.iter().enumerate() {
            let mount = Mount { index, support, shaft_dof: dofs.deflection(support.node) };
            add_ring(&mut m, &mut c, &mut k, &dofs, &mount);
        }
        SystemMatrices { dofs, m, c, k, s, g, unbalance }
    }

    /// Number of complex DOFs.
    pub fn size(&self) -> usize {
        self.dofs.len()
    }

    /// Velocity matrix D(Ω) = C − jΩG (Eq. 14, docs/model.md).
    pub fn damping_at(&self, speed: f64) -> Mat<c64> {
        let n = self.size();
        Mat::from_fn(n, n, |i, j| c64::new(self.c[(i, j)], -speed * self.g[(i, j)]))
    }

    /// Effective stiffness K − P·S for a static axial load P (N).
    pub fn stiffness_at(&self, load: f64) -> Mat<f64> {
        let n = self.size();
        Mat::from_fn(n, n, |i, j| self.k[(i, j)] - load * self.s[(i, j)])
    }
}

/// Where a ring sits: its index in the model, the ring and circuit, and the shaft's
/// deflection DOF there.
struct Mount<'a> {
    index: usize,
    support: &'a RingSupport,
    shaft_dof: usize,
}

/// Ring, bearing and shunt of one ring (Eq. 7–11, A8, and docs/model.md for open/short).
fn add_ring(m: &mut Mat<f64>, c: &mut Mat<f64>, k: &mut Mat<f64>, dofs: &DofMap, mount: &Mount<'_>) {
    let Mount { index, support, shaft_dof } = *mount;
    let (ring, circuit) = (&support.ring, &support.circuit);
    let a = dofs.ring(index);
    m[(a, a)] += ring.m_b;
    add_spring(c, shaft_dof, a, ring.eta);
    add_spring(k, shaft_dof, a, ring.k_eq());
    let k_eq2 = ring.k_eq2();
    let ground = match circuit.state {
        CircuitState::Open | CircuitState::Closed => ring.k_eq1() + k_eq2,
        CircuitState::Short => ring.k_eq1(),
    };
    k[(a, a)] += ground;
    if circuit.state != CircuitState::Closed {
        return;
    }
    // Eq. (A8): energy ½k_eq2(a − Σq̃ᵢ)² + Σ ½γq̃ᵢ²/C_fi, kinetic ½γLᵢq̃̇ᵢ², dissipation γRᵢ.
    let gamma = ring.gamma();
    let nb = circuit.branches.len();
    for (i, b) in circuit.branches.iter().enumerate() {
        let qi = dofs.charge(index, i);
        m[(qi, qi)] += gamma * b.inductance;
        c[(qi, qi)] += gamma * b.resistance;
        k[(qi, qi)] += gamma / b.c_f;
        k[(a, qi)] -= k_eq2;
        k[(qi, a)] -= k_eq2;
        for j in 0..nb {
            k[(qi, dofs.charge(index, j))] += k_eq2;
        }
    }
}

/// The system in real coordinates (the general path): every complex DOF of [`DofMap`]
/// becomes two real ones, its v and w parts, the v parts first: real DOF `i` is the v of
/// complex DOF `i`, real DOF `n + i` its w (`n` the complex size). With u = v + jw the
/// complex system splits into
///
/// `M v̈ + C v̇ + ΩG ẇ + K v = Re Q`, `M ẅ + C ẇ − ΩG v̇ + K w = Im Q`,
///
/// so M → diag(M, M), C → diag(C, C), K → diag(K, K), S → diag(S, S) and −jΩG → Ω·G_r
/// with G_r = [[0, G], [−G, 0]] (skew) on the velocities; then each bearing's and seal's
/// 2×2 matrices at the speed are added at its node's deflection (x = v, y = w). The
/// unbalance force Ω²·q·e^{jΩt} of the complex form is, in each plane, the real part of
/// Ω²·[q; −jq]·e^{jΩt}.
#[derive(Debug, Clone)]
pub struct GeneralSystem {
    /// The complex DOF layout (real DOF `i` and `n + i` are complex DOF `i`'s v and w).
    pub dofs: DofMap,
    /// Speed Ω the supports' coefficients were taken at (rad/s).
    pub speed: f64,
    /// diag(M, M) (kg, and γL for charges).
    pub m: Mat<f64>,
    /// diag(C, C) plus the supports' damping matrices at Ω (real, not symmetric in general).
    pub c: Mat<f64>,
    /// diag(K, K) plus the supports' stiffness matrices at Ω (not symmetric in general).
    pub k: Mat<f64>,
    /// diag(S, S) per unit axial load (1/m).
    pub s: Mat<f64>,
    /// G_r = [[0, G], [−G, 0]] per unit speed (kg·m²); enters as +Ω·G_r on the velocities.
    pub g: Mat<f64>,
    /// Unbalance per unit Ω², [q; −jq] (kg·m): the force in each plane is
    /// Re(Ω²·unbalance·e^{jΩt}).
    pub unbalance: Vec<c64>,
}

impl GeneralSystem {
    /// The real-coordinate system of `iso` (the model's assembly without the bearings'
    /// and seals' stiffness and damping: [`SystemMatrices::assemble_with`]) with
    /// `bearings` at speed `speed` (rad/s).
    pub fn new(iso: &SystemMatrices, bearings: &[crate::model::Bearing], speed: f64) -> GeneralSystem {
        let n = iso.size();
        let diag = |a: &Mat<f64>| {
            Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
                (true, true) => a[(i, j)],
                (false, false) => a[(i - n, j - n)],
                _ => 0.0,
            })
        };
        let (mut c, mut k) = (diag(&iso.c), diag(&iso.k));
        let g = Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
            (true, false) => iso.g[(i, j - n)],
            (false, true) => -iso.g[(i - n, j)],
            _ => 0.0,
        });
        for b in bearings {
            let d = iso.dofs.deflection(b.node);
            let at = b.matrices_at(speed);
            for (r, row) in [d, n + d].into_iter().enumerate() {
                for (s, col) in [d, n + d].into_iter().enumerate() {
                    k[(row, col)] += at.k[r][s];
                    c[(row, col)] += at.c[r][s];
                }
            }
        }
        let mut unbalance = iso.unbalance.clone();
        unbalance.extend(iso.unbalance.iter().map(|q| c64::new(q.im, -q.re)));
        GeneralSystem { dofs: iso.dofs.clone(), speed, m: diag(&iso.m), c, k, s: diag(&iso.s), g, unbalance }
    }

    /// Number of real DOFs (twice the complex ones).
    pub fn size(&self) -> usize {
        self.m.nrows()
    }

    /// The real DOF of complex DOF `dof` in plane `plane` (0: v, x; 1: w, y).
    pub fn real_dof(&self, dof: usize, plane: usize) -> usize {
        plane * self.dofs.len() + dof
    }

    /// Velocity matrix D = C + Ω·G_r at the system's speed.
    pub fn damping(&self) -> Mat<f64> {
        let n = self.size();
        Mat::from_fn(n, n, |i, j| self.c[(i, j)] + self.speed * self.g[(i, j)])
    }

    /// Effective stiffness K − P·S for a static axial load P (N).
    pub fn stiffness_at(&self, load: f64) -> Mat<f64> {
        let n = self.size();
        Mat::from_fn(n, n, |i, j| self.k[(i, j)] - load * self.s[(i, j)])
    }

    /// The symmetric part (K + Kᵀ)/2 of the stiffness: the conservative part of the
    /// supports' forces (the skew part is circulatory).
    pub fn symmetric_stiffness(&self) -> Mat<f64> {
        let n = self.size();
        Mat::from_fn(n, n, |i, j| 0.5 * (self.k[(i, j)] + self.k[(j, i)]))
    }
}

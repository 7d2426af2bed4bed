//! Swarm geometry: where the agents sit relative to the swarm's centre of mass, and who hears
//! whom.
//!
//! The swarm moves rigidly (paper section 3: "we let the swarm move as a whole without changing
//! the agents' relative positions"), so the neighbour lists and the bearings are computed once per
//! run. They are built with a uniform grid of cells one perception range wide, so building them
//! costs O(N) for any swarm of bounded density (10,000 agents take milliseconds), not O(N²).

use nalgebra::{Point2, Vector2};
use rand::Rng;
use serde::{Deserialize, Serialize};

/// The outline the agents are scattered in, centred on the origin. Lengths are in perception
/// ranges R.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A disk of this diameter (the paper: 6 R for 61 agents).
    Disk {
        /// Diameter in R.
        diameter: f64,
    },
    /// An axis-aligned rectangle.
    Rectangle {
        /// Extent along x, in R.
        width: f64,
        /// Extent along y, in R.
        height: f64,
    },
    /// Not random: the N nodes of a triangular lattice nearest the centre (a node at the
    /// centre; ties broken by angle). With a spacing of 0.75 R, 61 agents are exactly the nodes
    /// within 3 R, a hexagon of the centre and four rings (1 + 6 + 12 + 18 + 24) filling a disk
    /// of diameter 6 R, and have 5.1 neighbours on average: the paper's N = 61, D = 6 R and "on
    /// average five neighbours" (random placement in that disk, redrawn until connected, gives
    /// about 6.1, 5.8 without the redraw; see docs/reproduction.md).
    Lattice {
        /// Distance between neighbouring nodes, in R.
        spacing: f64,
    },
}

impl Shape {
    /// A point drawn uniformly inside the shape; `None` for a lattice, which is not random.
    pub fn sample(&self, rng: &mut impl Rng) -> Option<Vector2<f64>> {
        Some(match *self {
            Shape::Lattice { .. } => return None,
            Shape::Disk { diameter } => {
                let r = 0.5 * diameter * rng.random::<f64>().sqrt();
                let a = std::f64::consts::TAU * rng.random::<f64>();
                Vector2::new(r * a.cos(), r * a.sin())
            }
            Shape::Rectangle { width, height } => Vector2::new(
                width * (rng.random::<f64>() - 0.5),
                height * (rng.random::<f64>() - 0.5),
            ),
        })
    }

    /// The same outline scaled so that `to` agents have the density `from` agents had (a
    /// lattice keeps its spacing: it grows by itself).
    pub fn scaled_for(&self, from: usize, to: usize) -> Shape {
        let k = (to as f64 / from.max(1) as f64).sqrt();
        match *self {
            Shape::Lattice { .. } => *self,
            Shape::Disk { diameter } => Shape::Disk {
                diameter: diameter * k,
            },
            Shape::Rectangle { width, height } => Shape::Rectangle {
                width: width * k,
                height: height * k,
            },
        }
    }
}

/// One neighbour of a sender: who hears it and from which direction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Link {
    /// The neighbour's index.
    pub agent: u32,
    /// The direction in which this neighbour hears the sender (direction of reception):
    /// `atan2(sender − neighbour)`, radians in `(−π, π]`, counter-clockwise from +x.
    #[serde(with = "crate::json")]
    pub bearing: f32,
}

/// The agents' positions relative to the centre of mass and their neighbour lists.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Swarm {
    #[serde(with = "crate::json")]
    offsets: Vec<Vector2<f64>>,
    #[serde(with = "crate::json")]
    range: f64,
    start: Vec<u32>,
    links: Vec<Link>,
}

/// The shape is too sparse for the number of agents: no connected placement was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlacementError {
    /// Redraw rounds tried (0: a lattice, which is never redrawn).
    pub rounds: u32,
}

impl std::fmt::Display for PlacementError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.rounds == 0 {
            return write!(
                f,
                "a lattice is disconnected: its spacing exceeds the range"
            );
        }
        write!(
            f,
            "no connected placement after {} redraw rounds: too few agents for the shape",
            self.rounds
        )
    }
}

impl std::error::Error for PlacementError {}

const MAX_ROUNDS: u32 = 10_000;

impl Swarm {
    /// Scatters `n` agents uniformly in `shape`. While the swarm is disconnected (some agent
    /// cannot reach another through neighbours within `range`), every agent outside the largest
    /// connected group is redrawn. The offsets are then shifted so that the centre of mass is the
    /// origin. A [`Shape::Lattice`] is not random: `rng` is not used.
    ///
    /// # Errors
    /// [`PlacementError`] if no connected placement is found within 10,000 redraw rounds (a
    /// lattice: at once, if its spacing exceeds `range`).
    pub fn place(
        n: usize,
        shape: Shape,
        range: f64,
        rng: &mut impl Rng,
    ) -> Result<Swarm, PlacementError> {
        if let Shape::Lattice { spacing } = shape {
            return placed_lattice(n, spacing, range);
        }
        let mut draw = || shape.sample(rng).unwrap_or_else(Vector2::zeros);
        let mut offsets: Vec<Vector2<f64>> = (0..n).map(|_| draw()).collect();
        for _ in 0..MAX_ROUNDS {
            let swarm = Swarm::from_offsets(offsets, range);
            let labels = swarm.components();
            let Some(largest) = largest_label(&labels) else {
                return Ok(swarm); // no agents
            };
            if labels.iter().all(|&l| l == largest) {
                return Ok(swarm.recentred());
            }
            offsets = swarm.offsets;
            for (o, &l) in offsets.iter_mut().zip(&labels) {
                if l != largest {
                    *o = draw();
                }
            }
        }
        Err(PlacementError { rounds: MAX_ROUNDS })
    }

    /// A swarm with exactly these offsets (not recentred) and neighbours within `range`.
    pub fn from_offsets(offsets: Vec<Vector2<f64>>, range: f64) -> Swarm {
        let (start, links) = neighbour_lists(&offsets, range);
        Swarm {
            offsets,
            range,
            start,
            links,
        }
    }

    fn recentred(mut self) -> Swarm {
        let n = self.offsets.len().max(1) as f64;
        let mean = self.offsets.iter().sum::<Vector2<f64>>() / n;
        for o in &mut self.offsets {
            *o -= mean;
        }
        self
    }

    /// Number of agents.
    pub fn len(&self) -> usize {
        self.offsets.len()
    }

    /// True for a swarm without agents.
    pub fn is_empty(&self) -> bool {
        self.offsets.is_empty()
    }

    /// Perception range.
    pub fn range(&self) -> f64 {
        self.range
    }

    /// Each agent's position relative to the centre of mass.
    pub fn offsets(&self) -> &[Vector2<f64>] {
        &self.offsets
    }

    /// Agent `i`'s position when the centre of mass is at `centre`.
    pub fn position(&self, i: usize, centre: Point2<f64>) -> Point2<f64> {
        centre + self.offsets[i]
    }

    /// The agents that hear agent `i`, by increasing index, each with the bearing at which it
    /// hears `i`. (Neighbourhood is symmetric: these are also the agents `i` hears.)
    #[inline]
    pub fn neighbours(&self, i: usize) -> &[Link] {
        &self.links[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// Mean number of neighbours.
    pub fn mean_degree(&self) -> f64 {
        self.links.len() as f64 / self.len().max(1) as f64
    }

    /// Component label of every agent (the smallest index in its connected group).
    pub fn components(&self) -> Vec<u32> {
        let n = self.len();
        let mut label = vec![u32::MAX; n];
        let mut stack = Vec::new();
        for root in 0..n {
            if label[root] != u32::MAX {
                continue;
            }
            label[root] = root as u32;
            stack.push(root);
            while let Some(i) = stack.pop() {
                for l in self.neighbours(i) {
                    let j = l.agent as usize;
                    if label[j] == u32::MAX {
                        label[j] = root as u32;
                        stack.push(j);
                    }
                }
            }
        }
        label
    }

    /// True if every agent can reach every other through neighbours.
    pub fn is_connected(&self) -> bool {
        let labels = self.components();
        labels.iter().all(|&l| l == 0)
    }
}

/// [`Swarm::place`] of a lattice: the same swarm every time, so each thread keeps the last
/// few it made (a sweep places the same lattice for every run; its neighbour lists, with an
/// `atan2` per link, were a twentieth of a one-period run).
fn placed_lattice(n: usize, spacing: f64, range: f64) -> Result<Swarm, PlacementError> {
    type Key = (usize, u64, u64);
    const KEPT: usize = 8;
    thread_local! {
        static MADE: std::cell::RefCell<Vec<(Key, Swarm)>> = const { std::cell::RefCell::new(Vec::new()) };
    }
    let key = (n, spacing.to_bits(), range.to_bits());
    if let Some(s) = MADE.with_borrow(|m| m.iter().find(|(k, _)| *k == key).map(|(_, s)| s.clone()))
    {
        return Ok(s);
    }
    let swarm = Swarm::from_offsets(lattice(n, spacing), range);
    if !swarm.is_connected() {
        return Err(PlacementError { rounds: 0 });
    }
    let swarm = swarm.recentred();
    MADE.with_borrow_mut(|m| {
        if m.len() == KEPT {
            m.remove(0);
        }
        m.push((key, swarm.clone()));
    });
    Ok(swarm)
}

/// The `n` nodes of the triangular lattice with the given spacing (one node at the origin, one
/// along +x) nearest the origin; ties in distance are broken by angle, so the set is
/// deterministic.
pub fn lattice(n: usize, spacing: f64) -> Vec<Vector2<f64>> {
    if n == 0 || !(spacing.is_finite() && spacing > 0.0) {
        return Vec::new();
    }
    // Nodes within `rings` steps; enough once 3 r (r + 1) + 1 ≥ n with a ring to spare,
    // since the n nearest by distance all lie within that many rings.
    let mut rings = 1i64;
    while 3 * rings * (rings + 1) + 1 < 2 * n as i64 {
        rings += 1;
    }
    let rings = rings + 1;
    let h = 0.5 * 3f64.sqrt();
    let mut nodes: Vec<(i64, f64, Vector2<f64>)> = Vec::new();
    for j in -rings..=rings {
        for i in -rings..=rings {
            if (i + j).abs() > rings {
                continue;
            }
            // Squared distance in units of spacing² is the integer i² + i j + j².
            let d2 = i * i + i * j + j * j;
            let v = Vector2::new(
                spacing * (i as f64 + 0.5 * j as f64),
                spacing * h * j as f64,
            );
            let angle = v.y.atan2(v.x).rem_euclid(std::f64::consts::TAU);
            nodes.push((d2, angle, v));
        }
    }
    nodes.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    nodes.into_iter().take(n).map(|(_, _, v)| v).collect()
}

/// The label held by most agents (the lowest such label on a tie).
fn largest_label(labels: &[u32]) -> Option<u32> {
    let mut count = vec![0u32; labels.len()];
    for &l in labels {
        count[l as usize] += 1;
    }
    count
        .iter()
        .enumerate()
        .max_by_key(|&(i, &c)| (c, std::cmp::Reverse(i)))
        .map(|(i, _)| i as u32)
}

/// At most this many grid cells along each axis in [`neighbour_lists`]: 1024 × 1024 cells, 4 MB
/// of counts. A swarm within 1023 ranges along both axes (every scenario's: at most
/// [`MAX_EXTENT`](crate::scenario::MAX_EXTENT) = 1000 R) gets cells exactly one range wide.
pub const MAX_GRID_CELLS_PER_AXIS: usize = 1024;

/// Neighbour lists in compressed form (`start[i]..start[i+1]` indexes `links`), every pair within
/// `range` (inclusive), sorted by index. A uniform grid of cells at least `range` wide: each
/// agent only looks at the 3 × 3 cells around its own.
///
/// The cells are `range` wide unless the points spread over more than
/// [`MAX_GRID_CELLS_PER_AXIS`] ranges along an axis; then they are wider, so that the grid never
/// has more than 1024 × 1024 cells however far apart the points are (the lists are the same,
/// only more pairs are compared). Points with a non-finite coordinate have no neighbours.
pub fn neighbour_lists(points: &[Vector2<f64>], range: f64) -> (Vec<u32>, Vec<Link>) {
    let n = points.len();
    let mut start = Vec::with_capacity(n + 1);
    let mut links = Vec::new();
    start.push(0u32);
    if n == 0 || range.is_nan() || range <= 0.0 {
        start.resize(n + 1, 0);
        return (start, links);
    }
    let finite = |p: &&Vector2<f64>| p.x.is_finite() && p.y.is_finite();
    let first = points
        .iter()
        .find(finite)
        .copied()
        .unwrap_or_else(Vector2::zeros);
    let (mut lo, mut hi) = (first, first);
    for p in points.iter().filter(finite) {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    // Cells one range wide, or wider if the extent would need more than the maximum: then
    // `extent / width` is at most `MAX - 1` (an infinite extent, from points near ±f64::MAX,
    // gives infinite cells: one cell holds everything).
    let most = (MAX_GRID_CELLS_PER_AXIS - 1) as f64;
    let width = range.max((hi.x - lo.x) / most).max((hi.y - lo.y) / most);
    // `as` saturates and maps NaN (a non-finite point) to 0; the caller clamps to the grid.
    let cell_of = |v: f64, lo: f64| ((v - lo) / width).floor().max(0.0) as usize;
    let nx = cell_of(hi.x, lo.x).min(MAX_GRID_CELLS_PER_AXIS - 1) + 1;
    let ny = cell_of(hi.y, lo.y).min(MAX_GRID_CELLS_PER_AXIS - 1) + 1;
    let cell = |p: &Vector2<f64>| {
        (
            cell_of(p.x, lo.x).min(nx - 1),
            cell_of(p.y, lo.y).min(ny - 1),
        )
    };
    // Counting sort of the agents into cells.
    let mut cell_start = vec![0u32; nx * ny + 1];
    for p in points {
        let (cx, cy) = cell(p);
        cell_start[cy * nx + cx + 1] += 1;
    }
    for c in 1..cell_start.len() {
        cell_start[c] += cell_start[c - 1];
    }
    let mut fill = cell_start.clone();
    let mut members = vec![0u32; n];
    for (i, p) in points.iter().enumerate() {
        let (cx, cy) = cell(p);
        let c = cy * nx + cx;
        members[fill[c] as usize] = i as u32;
        fill[c] += 1;
    }
    let r2 = range * range;
    let mut mine = Vec::new();
    for (i, p) in points.iter().enumerate() {
        let (cx, cy) = cell(p);
        mine.clear();
        for y in cy.saturating_sub(1)..=(cy + 1).min(ny - 1) {
            for x in cx.saturating_sub(1)..=(cx + 1).min(nx - 1) {
                let c = y * nx + x;
                for &j in &members[cell_start[c] as usize..cell_start[c + 1] as usize] {
                    // From neighbour j toward agent i: the direction in which j hears i.
                    let d = p - points[j as usize];
                    if j as usize != i && d.norm_squared() <= r2 {
                        mine.push(Link {
                            agent: j,
                            bearing: d.y.atan2(d.x) as f32,
                        });
                    }
                }
            }
        }
        mine.sort_unstable_by_key(|l| l.agent);
        links.extend_from_slice(&mine);
        start.push(links.len() as u32);
    }
    (start, links)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_papers_lattice_fills_a_disk_of_6_r_with_five_neighbours_on_average() {
        let mut rng = rand_pcg::Pcg64Mcg::new(1);
        let s = Swarm::place(61, Shape::Lattice { spacing: 0.75 }, 1.0, &mut rng).unwrap();
        assert_eq!(s.len(), 61);
        let far = s.offsets().iter().map(|o| o.norm()).fold(0.0, f64::max);
        assert!((far - 3.0).abs() < 1e-9, "{far}");
        // 6 corners with 3 neighbours, 18 other rim nodes with 4, 37 inner nodes with 6.
        assert!((s.mean_degree() - 312.0 / 61.0).abs() < 1e-12);
        let mean: Vector2<f64> = s.offsets().iter().sum::<Vector2<f64>>() / 61.0;
        assert!(mean.norm() < 1e-12);
        // Symmetric: as many nodes on each side of any line through the centre.
        let east = s.offsets().iter().filter(|o| o.x > 1e-9).count();
        let west = s.offsets().iter().filter(|o| o.x < -1e-9).count();
        assert_eq!(east, west);
        assert!(Shape::Lattice { spacing: 0.75 }.sample(&mut rng).is_none());
        // Too sparse to be connected.
        let e = Swarm::place(7, Shape::Lattice { spacing: 1.5 }, 1.0, &mut rng).unwrap_err();
        assert!(e.to_string().contains("spacing"), "{e}");
        // Other sizes: the nearest nodes, deterministic.
        assert_eq!(lattice(1000, 0.75), lattice(1000, 0.75));
        assert_eq!(lattice(7, 1.0).len(), 7);
        assert!(lattice(7, 1.0).iter().all(|v| v.norm() < 1.0 + 1e-9));
    }
    use rand::SeedableRng;
    use rand_pcg::Pcg32;

    fn brute(points: &[Vector2<f64>], range: f64) -> Vec<Vec<u32>> {
        (0..points.len())
            .map(|i| {
                (0..points.len())
                    .filter(|&j| j != i && (points[j] - points[i]).norm() <= range)
                    .map(|j| j as u32)
                    .collect()
            })
            .collect()
    }

    #[test]
    fn grid_neighbours_equal_all_pairs() {
        let mut rng = Pcg32::seed_from_u64(1);
        let shape = Shape::Disk { diameter: 12.0 };
        let pts: Vec<_> = (0..400).map(|_| shape.sample(&mut rng).unwrap()).collect();
        let s = Swarm::from_offsets(pts.clone(), 1.0);
        let b = brute(&pts, 1.0);
        for (i, want) in b.iter().enumerate() {
            let got: Vec<u32> = s.neighbours(i).iter().map(|l| l.agent).collect();
            assert_eq!(&got, want, "agent {i}");
        }
    }

    #[test]
    fn bearings_point_from_receiver_to_sender() {
        let pts = vec![
            Vector2::new(0.0, 0.0),
            Vector2::new(0.5, 0.0),
            Vector2::new(0.0, -0.5),
        ];
        let s = Swarm::from_offsets(pts, 1.0);
        // Agent 0 sends: agent 1 (east of it) hears it from the west, agent 2 (south) from the north.
        let n0 = s.neighbours(0);
        assert_eq!(n0[0].agent, 1);
        assert!((n0[0].bearing - std::f32::consts::PI).abs() < 1e-6, "west");
        assert_eq!(n0[1].agent, 2);
        assert!(
            (n0[1].bearing - std::f32::consts::FRAC_PI_2).abs() < 1e-6,
            "north"
        );
        // Agent 1 sends: agent 0 hears it from the east.
        assert!(s.neighbours(1)[0].bearing.abs() < 1e-6, "east");
    }

    #[test]
    fn placements_are_connected_centred_and_about_five_neighbours() {
        let mut degree = 0.0;
        for seed in 0..20 {
            let mut rng = Pcg32::seed_from_u64(seed);
            let s = Swarm::place(61, Shape::Disk { diameter: 6.0 }, 1.0, &mut rng).unwrap();
            assert!(s.is_connected());
            let c: Vector2<f64> = s.offsets().iter().sum::<Vector2<f64>>() / 61.0;
            assert!(c.norm() < 1e-9);
            degree += s.mean_degree() / 20.0;
        }
        assert!((4.5..7.0).contains(&degree), "mean degree {degree}");
    }

    #[test]
    fn far_apart_points_get_a_bounded_grid_and_the_same_neighbours() {
        // 100,000 ranges apart, then 10^300: one range wide, the grid would need 10^10 cells
        // (an abort) or overflow; wider cells give the same lists.
        for far in [1e5, 1e300, f64::MAX] {
            let pts = vec![
                Vector2::new(0.0, 0.0),
                Vector2::new(0.5, 0.0),
                Vector2::new(far, far),
                Vector2::new(far, far - 0.75),
                Vector2::new(-far, 3.0),
            ];
            let s = Swarm::from_offsets(pts.clone(), 1.0);
            let got: Vec<Vec<u32>> = (0..pts.len())
                .map(|i| s.neighbours(i).iter().map(|l| l.agent).collect())
                .collect();
            if far < f64::MAX {
                assert_eq!(got, brute(&pts, 1.0), "{far}");
            }
            assert_eq!(got[0], vec![1], "{far}");
            assert_eq!(got[1], vec![0], "{far}");
        }
        // Points that are not finite have no neighbours and break nothing.
        let pts = vec![
            Vector2::new(0.0, 0.0),
            Vector2::new(f64::NAN, 0.0),
            Vector2::new(f64::INFINITY, f64::NEG_INFINITY),
            Vector2::new(0.25, 0.0),
        ];
        let s = Swarm::from_offsets(pts, 1.0);
        assert_eq!(
            s.neighbours(0).iter().map(|l| l.agent).collect::<Vec<_>>(),
            vec![3]
        );
        assert!(s.neighbours(1).is_empty() && s.neighbours(2).is_empty());
    }

    #[test]
    fn a_too_sparse_shape_is_an_error() {
        let mut rng = Pcg32::seed_from_u64(3);
        let e = Swarm::place(3, Shape::Disk { diameter: 1000.0 }, 1.0, &mut rng);
        assert!(e.is_err());
    }
}

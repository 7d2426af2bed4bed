//! The seed stages of `swarm reproduce`, named in one place. Every run of the page draws from
//! `derive(--seed, [offset])` ([`Stage::seed`](crate::stage::Stage::seed)); each experiment
//! owns a [`Block`] of offsets, and the blocks are listed in `BLOCKS`, where a test checks
//! that no two overlap. A new experiment takes a free block here, so it can never reuse
//! another's seeds by accident. Experiments that share seeds on purpose say so: the sensor
//! experiment reruns the main placement's courses' seeds with one reading per period
//! ([`COURSES`]; the courses' own runs, both placements, are tapped as they run, not rerun), and the refractory
//! experiment reruns the waves figure's wave ([`WAVE`]).
//!
//! The offsets are the ones the page has always used (the page does not change); the speed
//! runs, which set only the page's timing line, now count their sizes, not their agents.

/// A block of stage offsets: `first + i × stride + j` for `j < stride` and `i × stride + j <
/// len` (one dimension: `stride == len`).
#[derive(Clone, Copy, Debug)]
pub struct Block {
    /// What draws from it.
    pub name: &'static str,
    first: u64,
    len: u64,
    stride: u64,
}

/// A stage offset, from a [`Block`]: the only thing a stage's seed is made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Offset(u64);

impl Offset {
    /// The number `derive` takes.
    pub fn get(self) -> u64 {
        self.0
    }
}

impl Block {
    const fn new(name: &'static str, first: u64, len: u64) -> Block {
        Block {
            name,
            first,
            len,
            stride: len,
        }
    }

    const fn grid(name: &'static str, first: u64, len: u64, stride: u64) -> Block {
        Block {
            name,
            first,
            len,
            stride,
        }
    }

    /// Offset `k` of a one-dimensional block.
    ///
    /// # Panics
    /// If `k` is not below its length: the block is too small for the experiment, a bug
    /// that this catches before a run draws another block's seeds.
    pub fn at(self, k: usize) -> Offset {
        self.at2(0, k)
    }

    /// Offset `(i, j)` of a two-dimensional block: `first + i × stride + j`.
    ///
    /// # Panics
    /// If `j` is not below the stride or the offset beyond the block (as [`Block::at`]).
    pub fn at2(self, i: usize, j: usize) -> Offset {
        let k = (i as u64) * self.stride + j as u64;
        assert!(
            (j as u64) < self.stride && k < self.len,
            "seed block {}: ({i}, {j}) is beyond its {} offsets",
            self.name,
            self.len
        );
        Offset(self.first + k)
    }

    #[cfg(test)]
    fn range(self) -> std::ops::Range<u64> {
        self.first..self.first + self.len
    }
}

/// Figs. 5 and 8's runs, per field.
pub const RUN_FIGURES: Block = Block::new("run figures", 0, 2);
/// The sweeps with the random placement, per field.
pub const SWEEPS_RANDOM: Block = Block::new("sweeps, random placement", 10, 2);
/// The sweeps with the lattice, per field.
pub const SWEEPS_LATTICE: Block = Block::new("sweeps, lattice", 12, 2);
/// The direction maps, per scene.
pub const MAPS: Block = Block::new("direction maps", 20, 3);
/// The cloud's radial profile.
pub const CLOUD_PROFILE: Block = Block::new("cloud profile", 30, 1);
/// The averaged courses, per field (stride 2) and placement (the runs are tapped as they
/// run; the sensor experiment reruns the main placement's seeds).
pub const COURSES: Block = Block::grid("averaged courses", 40, 4, 2);
/// The cycle-length sweeps, per cycle.
pub const CYCLE_SWEEPS: Block = Block::new("cycle-length sweeps", 50, 7);
/// The waves heard per cycle length.
pub const CYCLE_WAVES: Block = Block::new("cycle-length waves heard", 60, 7);
/// The speed runs, per size.
pub const SPEED: Block = Block::new("speed", 70, 3);
/// The placements' neighbour counts.
pub const PLACEMENT_STATS: Block = Block::new("placements", 80, 1);
/// The caption's cloud: its map.
pub const CAPTION_MAP: Block = Block::new("caption's cloud map", 90, 1);
/// The caption's cloud: its profile.
pub const CAPTION_PROFILE: Block = Block::new("caption's cloud profile", 91, 1);
/// Fig. 2's wave; the refractory experiment reruns it.
pub const WAVE: Block = Block::new("one wave", 95, 1);
/// The shapes.
pub const SHAPES: Block = Block::new("shapes", 200, 1);
/// Beyond the paper: success per field (stride 10) and measure.
pub const BEYOND_SUCCESS: Block = Block::grid("beyond: success", 300, 20, 10);
/// Beyond the paper: the profile per measure (stride 10) and x.
pub const BEYOND_PROFILE: Block = Block::grid("beyond: profile", 350, 20, 10);
/// Beyond the paper: per slope (stride 2) and measure, at the success line.
pub const BEYOND_SLOPES: Block = Block::grid("beyond: slopes", 380, 6, 2);
/// Beyond the paper: two quantities, per measure.
pub const BEYOND_TWO: Block = Block::new("beyond: two quantities", 390, 2);
/// The sensitivity tables, per knob (stride 10) and case.
pub const KNOBS: Block = Block::grid("sensitivity knobs", 500, 40, 10);
/// The gradient's slope: success.
pub const SLOPE_SUCCESS: Block = Block::new("slope: success", 550, 1);
/// The gradient's slope: the diversity at the line, per slope.
pub const SLOPE_DIVERSITY: Block = Block::new("slope: diversity", 560, 6);
/// The extent, per field (stride 2) and diameter.
pub const EXTENT: Block = Block::grid("extent", 570, 4, 2);
/// The sharp plateau, per placement (stride 10) and cycle.
pub const PLATEAU: Block = Block::grid("settle: plateau", 600, 20, 10);
/// The heading along the way, per field.
pub const HEADING: Block = Block::new("settle: heading", 620, 10);
/// The starting diversity, per field (stride 2) and placement.
pub const START: Block = Block::grid("settle: start", 630, 4, 2);
/// Steeper, faster: per slope.
pub const STEEP: Block = Block::new("settle: steep", 640, 10);
/// Indecision points against the swarm's size, per placement.
pub const INDECISION: Block = Block::new("indecision", 650, 2);
/// The direction maps with the other placement, per scene.
pub const MAPS_OTHER: Block = Block::new("direction maps, other placement", 660, 3);
/// The swarm's extent with the other placement, per field.
pub const EXTENT_OTHER: Block = Block::new("extent, other placement", 670, 2);
/// The radial profiles with the other placement: the text's cloud, the caption's.
pub const PROFILES_OTHER: Block = Block::new("cloud profiles, other placement", 680, 2);
/// Steeper, faster with the other placement: per slope.
pub const STEEP_OTHER: Block = Block::new("settle: steep, other placement", 690, 10);
/// The NumPy peer's work (timing only).
pub const PEER: Block = Block::new("peer work", 700, 1);

/// Every block, in order: what the test checks for overlaps.
#[cfg(test)]
const BLOCKS: &[Block] = &[
    RUN_FIGURES,
    SWEEPS_RANDOM,
    SWEEPS_LATTICE,
    MAPS,
    CLOUD_PROFILE,
    COURSES,
    CYCLE_SWEEPS,
    CYCLE_WAVES,
    SPEED,
    PLACEMENT_STATS,
    CAPTION_MAP,
    CAPTION_PROFILE,
    WAVE,
    SHAPES,
    BEYOND_SUCCESS,
    BEYOND_PROFILE,
    BEYOND_SLOPES,
    BEYOND_TWO,
    KNOBS,
    SLOPE_SUCCESS,
    SLOPE_DIVERSITY,
    EXTENT,
    PLATEAU,
    HEADING,
    START,
    STEEP,
    INDECISION,
    MAPS_OTHER,
    EXTENT_OTHER,
    PROFILES_OTHER,
    STEEP_OTHER,
    PEER,
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_two_blocks_share_a_seed() {
        for (i, a) in BLOCKS.iter().enumerate() {
            assert!(a.len > 0 && a.stride > 0 && a.stride <= a.len, "{a:?}");
            for b in &BLOCKS[i + 1..] {
                let (ra, rb) = (a.range(), b.range());
                assert!(
                    ra.end <= rb.start || rb.end <= ra.start,
                    "{} {ra:?} overlaps {} {rb:?}",
                    a.name,
                    b.name
                );
            }
        }
    }

    #[test]
    fn an_offset_beyond_its_block_is_refused() {
        assert_eq!(COURSES.at2(1, 1).get(), 43);
        assert_eq!(BEYOND_SLOPES.at2(2, 1).get(), 385);
        assert!(std::panic::catch_unwind(|| COURSES.at2(0, 2)).is_err());
        assert!(std::panic::catch_unwind(|| COURSES.at2(2, 0)).is_err());
        assert!(std::panic::catch_unwind(|| WAVE.at(1)).is_err());
    }
}

//! The hybrid engine's event queue: its keys, their unique priorities (time, class, bead,
//! key) and the hasher of its index map. Checkpoints store keys and priorities as they are.

use ordered_float::OrderedFloat;
use priority_queue::PriorityQueue;
use std::cmp::Reverse;

/// Queue keys (checkpoints store them as they are, [`super::saved::HybridState`]'s queue).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Key {
    /// The next output frame.
    Frame,
    /// A cluster (slot index).
    Cluster(u32),
    /// Predicted closing of the gap between free beads `c` and `c + 1`.
    FreeFree(u32),
    /// Predicted closing of a free end bead onto a wall (0 = left, 1 = right).
    Wall(u8),
    /// A crossing of `θ` by a soft wall's overlap with the end bead of a cluster, logged when
    /// the queue reaches it ([`super::walllog`]).
    WallLog(u8),
}

/// A key hashes as its unique [`Key::id`] alone (one `u64` through [`KeyHasher`]).
impl std::hash::Hash for Key {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        state.write_u64(self.id());
    }
}

/// The queue's hasher: a multiplicative (Fibonacci) hash of the key's id. The queue's index map
/// hashed every push, pop and removal with SipHash, ~2 % of a 1000-bead striker run's
/// instructions (`valgrind --tool=callgrind`); keys are small distinct integers, so one
/// multiplication spreads them over the table. Iteration order is never used (checkpoints sort
/// the entries, pops follow the unique priorities), so the choice of hash changes no output.
#[derive(Default)]
pub(super) struct KeyHasher(u64);

impl std::hash::Hasher for KeyHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0 ^ x).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
    fn finish(&self) -> u64 {
        self.0 ^ (self.0 >> 29)
    }
}

/// The event queue: keys by priority, hashed with [`KeyHasher`].
pub(super) type Queue = PriorityQueue<Key, Prio, std::hash::BuildHasherDefault<KeyHasher>>;

impl Key {
    /// Unique number of the key.
    pub(super) fn id(self) -> u64 {
        let index = match self {
            Key::Frame => 0,
            Key::Cluster(s) => s as u64,
            Key::FreeFree(c) => c as u64,
            Key::Wall(w) | Key::WallLog(w) => w as u64,
        };
        index << 3 | self.tag()
    }

    fn tag(self) -> u64 {
        match self {
            Key::Frame => 0,
            Key::Cluster(_) => 1,
            Key::FreeFree(_) => 2,
            Key::Wall(_) => 3,
            Key::WallLog(_) => 4,
        }
    }
}

/// Priority: earliest time first, then class (frames 0, events 1, steps 2), then bead index.
/// The last component (the key itself) makes every priority unique, so the pop order never
/// depends on the heap's insertion history (needed for bit-identical resumes).
pub type Prio = Reverse<(OrderedFloat<f64>, u8, u64, u64)>;

pub(super) fn prio(t: f64, class: u8, index: usize, key: Key) -> Prio {
    Reverse((
        OrderedFloat(t),
        class,
        (index as u64) << 3 | key.tag(),
        key.id(),
    ))
}

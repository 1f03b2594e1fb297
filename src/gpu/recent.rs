//! A map that keeps only its most recently used entries: the pipeline cache's store. A
//! long-lived process (the test suite, a study of many methods, the viewer switching scenes)
//! makes pipelines for many keys, and lavapipe holds each pipeline's compiled code (a test of
//! the Cornell box's 22 methods peaked at 462 MB, one of a heterogeneous medium's two at 1.24
//! GB), so an unbounded cache grew the test suite past 24 GiB (2026-12-07, three tests at once).

use std::collections::HashMap;
use std::hash::Hash;

/// At most `capacity` entries; inserting one more drops the least recently used (looked up or
/// inserted). Values still held elsewhere (an `Arc`'d pipeline a renderer uses) live on there.
pub struct Recent<K, V> {
    capacity: usize,
    clock: u64,
    entries: HashMap<K, (V, u64)>,
}

impl<K: Eq + Hash + Clone, V> Recent<K, V> {
    pub fn new(capacity: usize) -> Recent<K, V> {
        Recent { capacity: capacity.max(1), clock: 0, entries: HashMap::new() }
    }

    /// The value of `key`, now the most recently used.
    pub fn get(&mut self, key: &K) -> Option<&V> {
        self.clock += 1;
        let clock = self.clock;
        self.entries.get_mut(key).map(|(v, used)| {
            *used = clock;
            &*v
        })
    }

    /// Inserts `key`, dropping the least recently used entries beyond the capacity.
    pub fn insert(&mut self, key: K, value: V) {
        self.clock += 1;
        self.entries.insert(key, (value, self.clock));
        self.truncate(self.capacity);
    }

    /// Drops the least recently used entries until at most `keep` are left (a linear scan per
    /// entry dropped: capacities are tens, and an insert follows a compilation).
    pub fn truncate(&mut self, keep: usize) {
        while self.entries.len() > keep {
            let Some(oldest) = self.entries.iter().min_by_key(|(_, (_, used))| *used).map(|(k, _)| k.clone()) else { break };
            self.entries.remove(&oldest);
        }
    }

    #[cfg(test)]
    fn len(&self) -> usize {
        self.entries.len()
    }
}

#[cfg(test)]
mod tests {
    use super::Recent;

    #[test]
    fn keeps_the_most_recently_used() {
        let mut r = Recent::new(2);
        r.insert("a", 1);
        r.insert("b", 2);
        // "a" used after "b": "b" is the one to go.
        assert_eq!(r.get(&"a"), Some(&1));
        r.insert("c", 3);
        assert_eq!(r.len(), 2);
        assert_eq!(r.get(&"b"), None);
        assert_eq!((r.get(&"a").copied(), r.get(&"c").copied()), (Some(1), Some(3)));
        // Inserting a key again refreshes it and keeps the count.
        r.insert("a", 4);
        r.insert("d", 5);
        assert_eq!((r.get(&"a").copied(), r.get(&"c").copied(), r.get(&"d").copied()), (Some(4), None, Some(5)));
        // Truncated to one: the last looked up ("d") stays.
        r.truncate(1);
        assert_eq!((r.len(), r.get(&"a").copied(), r.get(&"d").copied()), (1, None, Some(5)));
    }
}

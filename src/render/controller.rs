//! How many samples fit a span of time: one controller for the three places that ask (the batch
//! loop's dispatch size, the target loop's rounds, the viewer's samples per UI frame). Each
//! measures seconds per sample its own way (GPU completion times, a round's wall time, a frame
//! minus the UI's share); what they share is the step: the count that would fill the aim,
//! approached by at most a factor of two per step (a measurement may be noisy or stale: a driver
//! compiling at the first dispatch, a preempted core), within [fewest, most].

/// A sample count steered towards the count that fills a time span.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleCount {
    k: f64,
    fewest: f64,
    most: f64,
    /// 1: move to the wanted count (within the factor of two); 0.5: the geometric middle, for a
    /// noisy per-step measurement (the viewer's single frames).
    damping: f64,
}

impl SampleCount {
    /// Starts at `start`, stays within [fewest, most].
    pub fn new(start: f64, fewest: f64, most: f64) -> SampleCount {
        SampleCount { k: start.clamp(fewest, most), fewest, most, damping: 1.0 }
    }

    /// Moves only part of the way (the exponent of wanted / current taken per step).
    pub fn damped(self, damping: f64) -> SampleCount {
        SampleCount { damping, ..self }
    }

    /// The current count.
    pub fn get(&self) -> f64 {
        self.k
    }

    /// One step towards the count that fills `aim` seconds at `seconds_per_sample`.
    pub fn fill(&mut self, aim: f64, seconds_per_sample: f64) -> f64 {
        self.towards(aim / seconds_per_sample.max(1e-12))
    }

    /// One step towards `wanted` samples.
    pub fn towards(&mut self, wanted: f64) -> f64 {
        let ratio = if wanted.is_finite() && wanted > 0.0 { (wanted / self.k).powf(self.damping) } else { 2.0 };
        self.k = (self.k * ratio.clamp(0.5, 2.0)).clamp(self.fewest, self.most);
        self.k
    }

    /// No measurement yet: double.
    pub fn grow(&mut self) -> f64 {
        self.towards(self.k * 2.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_at_most_double_or_halve_and_stay_within_bounds() {
        let mut c = SampleCount::new(1.0, 1.0, 100.0);
        // 1 ms per sample, 150 ms aim: 150 wanted, reached by doubling.
        let path: Vec<f64> = (0..9).map(|_| c.fill(0.15, 0.001)).collect();
        assert_eq!(path, vec![2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 100.0, 100.0, 100.0]);
        let mut c = SampleCount::new(64.0, 1.0, 1e6);
        assert_eq!(c.towards(1.0), 32.0);
        assert_eq!(c.towards(40.0), 40.0);
        let mut d = SampleCount::new(16.0, 1.0, 1e6).damped(0.5);
        assert_eq!(d.towards(64.0), 32.0);
        assert_eq!(d.towards(f64::NAN), 64.0);
    }
}

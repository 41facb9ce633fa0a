//! Resizing a scenario to a body count (for benchmarks and the window).

use super::contents::Scenario;
use super::format::Generator;

/// A scenario that cannot be resized to the count asked for: it has no
/// generators, or its generated bodies would then be numbered past the
/// bound on ids.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{origin}: {problem}")]
pub struct CannotResize {
    /// The scenario's origin.
    pub origin: String,
    /// What stands in the way.
    pub problem: String,
}

impl Scenario {
    /// This scenario with `count` generated bodies in all, shared among its
    /// generators in proportion to their counts (the rest to the last one).
    /// Explicit bodies stay.
    pub fn with_generated(&self, count: u64) -> Result<Scenario, CannotResize> {
        let counts: Vec<u64> = self.generators.iter().map(Generator::count).collect();
        let total: u64 = counts.iter().sum();
        let cannot = |problem: String| CannotResize {
            origin: self.origin.clone(),
            problem,
        };
        if counts.is_empty() {
            return Err(cannot(
                "has no generators, so its body count cannot be changed".to_owned(),
            ));
        }
        let mut scaled = self.clone();
        let mut given = 0;
        let last = counts.len() - 1;
        for (i, generator) in scaled.generators.iter_mut().enumerate() {
            let share = if i == last {
                count - given
            } else if total == 0 {
                0
            } else {
                (u128::from(count) * u128::from(counts[i]) / u128::from(total)) as u64
            };
            given += share;
            *generator.count_mut() = share;
        }
        // The check a file of this size would get when it loads.
        match scaled.generated_ids_problem() {
            Some(problem) => Err(cannot(format!("resized to {count} generated bodies: {problem}"))),
            None => Ok(scaled),
        }
    }
}

impl Generator {
    /// Bodies this generator makes.
    pub fn count(&self) -> u64 {
        match self {
            Generator::Cloud(c) => c.count,
            Generator::Shell(s) => s.count,
        }
    }

    fn count_mut(&mut self) -> &mut u64 {
        match self {
            Generator::Cloud(c) => &mut c.count,
            Generator::Shell(s) => &mut s.count,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_the_count_in_proportion() {
        let s = Scenario::parse(
            "Scenario(bodies: [Body(position: (0,0,0), mass: 10, role: Source)], generators: [
                Cloud(count: 100, center: (0,0,0), half_size: (100,100,100)),
                Shell(count: 300, around: 0, inner_radius: 30, outer_radius: 40),
            ])",
            "t",
        )
        .unwrap();
        let scaled = s.with_generated(1001).unwrap();
        let counts: Vec<u64> = scaled.generators.iter().map(Generator::count).collect();
        assert_eq!(counts, [250, 751]);
        assert_eq!(scaled.body_count(), 1002);
        assert_eq!(s.with_generated(0).unwrap().body_count(), 1);
        let empty = Scenario {
            generators: vec![],
            ..s
        };
        let error = empty.with_generated(5).unwrap_err();
        assert_eq!(
            error.to_string(),
            "t: has no generators, so its body count cannot be changed"
        );
    }

    #[test]
    fn a_resize_never_numbers_bodies_past_the_bound_on_ids() {
        let last = crate::resources::MAX_ID - 1;
        let s = Scenario::parse(
            &format!(
                "Scenario(bodies: [Body(id: {}, position: (0,0,0), mass: 10, role: Source)], generators: [
                    Shell(count: 2, around: 0, inner_radius: 30, outer_radius: 40),
                ])",
                last - 10
            ),
            "t",
        )
        .unwrap();
        assert_eq!(s.with_generated(10).unwrap().next_id(), crate::resources::MAX_ID);
        let error = s.with_generated(11).unwrap_err().to_string();
        assert!(
            error.starts_with("t: resized to 11 generated bodies: ") && error.contains("past the largest id"),
            "{error}"
        );
    }
}

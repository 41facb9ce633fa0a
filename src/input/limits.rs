//! The bounds on counts a user may ask for, and the command-line parsers
//! that enforce them with a message saying the bound.

/// The most updates one run may ask for: 10¹². At a microsecond an update
/// (the fastest a tiny scene runs) that is eleven days; counts up to it,
/// plus one for a progress display, never overflow.
pub const MAX_UPDATES: u64 = 1_000_000_000_000;

/// The most generated bodies `kessler run --bodies` accepts, in either
/// build: two million, the most the window draws at an interactive rate.
pub const MAX_RUN_BODIES: u64 = 2_000_000;

/// A whole number from `min` to `max`, with a message that says so (rather
/// than the parser's "invalid digit found in string").
fn whole_number(text: &str, min: u64, max: u64) -> Result<u64, String> {
    match text.trim().parse::<u64>() {
        Ok(value) if (min..=max).contains(&value) => Ok(value),
        _ => Err(format!("must be a whole number from {min} to {max}")),
    }
}

/// Parses a number of updates on the command line (`--steps`).
pub fn updates_arg(text: &str) -> Result<u64, String> {
    whole_number(text, 0, MAX_UPDATES)
}

/// Parses a number of generated bodies on the command line (`--bodies`).
pub fn run_bodies_arg(text: &str) -> Result<u64, String> {
    whole_number(text, 0, MAX_RUN_BODIES)
}

/// Parses a thread count on the command line (`--threads`): 1 to 256.
pub fn threads_arg(text: &str) -> Result<usize, String> {
    whole_number(text, 1, crate::execution::MAX_THREADS as u64).map(|n| n as usize)
}

/// Parses a count of members at once (`kessler ensemble --jobs`): 1 to
/// 10⁶, the most members an ensemble has.
pub fn jobs_arg(text: &str) -> Result<usize, String> {
    whole_number(text, 1, 1_000_000).map(|n| n as usize)
}

/// Parses a count of updates between two timeline rows (`--every`), or of
/// frames (`--frames`): 1 to 10¹².
pub fn positive_count_arg(text: &str) -> Result<u64, String> {
    whole_number(text, 1, MAX_UPDATES)
}

/// Parses updates per second on the command line (`--ups`): 1 to 600.
pub fn ups_arg(text: &str) -> Result<u32, String> {
    whole_number(text, 1, 600).map(|n| n as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_outside_their_bounds_say_the_bounds() {
        assert_eq!(updates_arg("0"), Ok(0));
        assert_eq!(updates_arg("1000000000000"), Ok(MAX_UPDATES));
        let says = Err("must be a whole number from 0 to 1000000000000".to_owned());
        for bad in ["-5", "1000000000001", "18446744073709551615", "1e3", "", "x"] {
            assert_eq!(updates_arg(bad), says, "{bad:?}");
        }
        assert_eq!(run_bodies_arg("2000000"), Ok(MAX_RUN_BODIES));
        assert!(run_bodies_arg("2000001").unwrap_err().contains("from 0 to 2000000"));
        for bad in ["0", "2.5", "-1", "99999999999999999999", "257"] {
            assert_eq!(threads_arg(bad), Err("must be a whole number from 1 to 256".to_owned()));
        }
        assert_eq!(
            (threads_arg("256"), ups_arg("600"), positive_count_arg("1")),
            (Ok(256), Ok(600), Ok(1))
        );
        assert!(ups_arg("-3").is_err() && positive_count_arg("0").is_err());
    }
}

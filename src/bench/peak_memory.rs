//! Peak memory of a benchmark run: the process's peak resident set size
//! (Linux's `VmHWM`), reset before each run so that each run's peak is its
//! own. Elsewhere, or where `/proc` cannot be read, there is no figure.

/// Starts a new peak: memory the allocator keeps from earlier runs goes back
/// to the system, then the high-water mark drops to what is resident now.
pub fn reset_peak_memory() {
    crate::memory::release_free_memory();
    // Linux ≥ 4.0; on failure the peak simply spans earlier runs too.
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// The peak resident set size since the last reset, in bytes.
pub fn peak_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_peak(&status)
}

/// `VmHWM` from the text of `/proc/self/status`, in bytes.
fn parse_peak(status: &str) -> Option<u64> {
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line
        .trim_start_matches("VmHWM:")
        .trim()
        .strip_suffix("kB")?
        .trim()
        .parse()
        .ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_high_water_mark_in_bytes() {
        let status = "Name:\tkessler\nVmPeak:\t  999 kB\nVmHWM:\t  232568 kB\nVmRSS:\t 1000 kB\n";
        assert_eq!(parse_peak(status), Some(232_568 * 1024));
        assert_eq!(parse_peak("VmRSS:\t 1 kB\n"), None);
    }

    #[test]
    fn peak_covers_what_was_touched_since_the_reset() {
        let Some(before) = peak_memory() else {
            return; // No /proc here: nothing to measure.
        };
        reset_peak_memory();
        let block = vec![1u8; 64 << 20];
        let peak = peak_memory().unwrap();
        assert!(block.iter().step_by(4096).all(|&b| b == 1));
        assert!(
            peak >= 64 << 20,
            "peak {peak} below the 64 MiB just touched (before: {before})"
        );
    }
}

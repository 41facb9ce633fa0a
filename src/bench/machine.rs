//! What machine a benchmark ran on: written beside its results as
//! `<stem>-machine.txt`, so that figures never travel without it.

use std::fmt::Write as _;

use crate::Simulation;
use crate::execution::{Execution, ExecutionMode, available_threads};
use crate::record::StateHash;
use crate::resources::SettingsPatch;
use crate::scenario::Scenario;
use crate::systems::Kernel;

/// A run whose state hash a machine report gives: two machines whose
/// hashes agree compute alike, and results whose hashes this code still
/// gives were measured on code that behaves as this code does (CI checks
/// every file in benches/results against them: docs/benchmarks.md,
/// "Regenerating the results").
#[derive(Clone, Copy, Debug)]
pub struct Reference {
    /// The report's key, `reference state hash`.
    pub key: &'static str,
    /// The scenario, as the report names it.
    pub file: &'static str,
    /// The scenario's text, built in.
    text: &'static str,
    /// Physics settings laid over the scenario's, as a `Set` event
    /// writes them: `(seed: 5)` (`()`: none).
    pub settings: &'static str,
    /// Updates run.
    pub updates: u64,
    /// What agreeing hashes show.
    meaning: &'static str,
}

/// The runs whose state hashes a report gives: a collapse under tree
/// gravity that shatters, with Kessler's default algorithms (swept
/// detection, the leapfrog), and a cascade of shatters with the thesis's
/// (`Discrete`, `SemiImplicitEuler`), which the benchmark configs measure
/// (the thesis scene itself is too sparse to shatter within a short run).
pub const REFERENCES: [Reference; 2] = [
    Reference {
        key: "reference state hash",
        file: "scenarios/collapse.ron",
        text: include_str!("../../scenarios/collapse.ron"),
        settings: "()",
        updates: 50,
        meaning: "equal hashes: this machine computes as that one",
    },
    Reference {
        key: "thesis state hash",
        file: "scenarios/cascade.ron",
        text: include_str!("../../scenarios/cascade.ron"),
        settings: "(collision_detection: Discrete, integrator: SemiImplicitEuler)",
        updates: 30,
        meaning: "the thesis's algorithms, as the benchmarks run them",
    },
];

impl Reference {
    /// The run's scenario, its settings laid over it.
    pub fn scenario(&self) -> Result<Scenario, String> {
        let mut scenario =
            Scenario::parse(self.text, &format!("{} (built in)", self.file)).map_err(|e| e.to_string())?;
        let settings: SettingsPatch = ron::from_str(self.settings).map_err(|e| e.to_string())?;
        settings.apply(&mut scenario.physics);
        Ok(scenario)
    }

    /// The state hash of the run, sequential on one thread (every
    /// execution gives the same).
    pub fn state_hash(&self) -> Result<StateHash, String> {
        let scenario = self.scenario()?;
        let execution = Execution::new(ExecutionMode::Sequential, 1).map_err(|e| e.to_string())?;
        let mut sim = Simulation::from_scenario(&scenario, execution).map_err(|e| e.to_string())?;
        sim.step(self.updates);
        Ok(sim.state_hash())
    }

    /// The report's value: the hash, and what it is.
    fn line(&self) -> String {
        match self.state_hash() {
            Ok(hash) => format!("{hash} ({}, {} updates; {})", self.run(), self.updates, self.meaning),
            Err(e) => format!("unknown ({e})"),
        }
    }

    /// The run in words: the scenario, and the settings laid over it.
    pub fn run(&self) -> String {
        match self.settings.trim_start_matches('(').trim_end_matches(')') {
            "" => self.file.to_owned(),
            settings => format!("{} with {settings}", self.file),
        }
    }

    /// The hash a report's text gives for this run, if it gives one.
    pub fn recorded_in(&self, report: &str) -> Option<StateHash> {
        let value = report
            .lines()
            .find_map(|l| l.strip_prefix(self.key)?.strip_prefix(": "))?;
        u64::from_str_radix(value.split_whitespace().next()?, 16)
            .ok()
            .map(StateHash)
    }
}

/// A `key: value` line per fact: CPU model, cores and threads, memory, OS,
/// rustc, Kessler's version and commit, the gravity kernel the processor
/// runs, the reference runs' state hashes, the date (UTC), and the command.
pub fn machine_report(command: &str) -> String {
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let mut out = String::new();
    let mut line = |key: &str, value: String| {
        let _ = writeln!(out, "{key}: {value}");
    };
    line(
        "cpu",
        cpu_model(&cpuinfo).unwrap_or_else(|| std::env::consts::ARCH.to_owned()),
    );
    line(
        "cores",
        physical_cores(&cpuinfo).map_or("unknown".into(), |n| n.to_string()),
    );
    line("hardware threads", available_threads().to_string());
    line("memory", memory_total().unwrap_or_else(|| "unknown".into()));
    line("os", os_name());
    line("rustc", env!("KESSLER_RUSTC_VERSION").to_owned());
    line(
        "kessler",
        format!("{} (commit {})", env!("CARGO_PKG_VERSION"), env!("KESSLER_GIT_COMMIT")),
    );
    line("gravity kernel", Kernel::best().name().to_owned());
    for reference in &REFERENCES {
        line(reference.key, reference.line());
    }
    line(
        "profile",
        if cfg!(debug_assertions) { "debug" } else { "release" }.to_owned(),
    );
    line("date", utc_now());
    line("command", command.to_owned());
    out
}

/// The plot's footer: the machine and the build the figures come from.
pub fn plot_footer() -> String {
    format!(
        "{}, {} hardware threads · Kessler {}, commit {} · {}",
        this_cpu(),
        available_threads(),
        env!("CARGO_PKG_VERSION"),
        env!("KESSLER_GIT_COMMIT"),
        utc_now()
    )
}

/// This machine's CPU model (its architecture if unknown).
pub fn this_cpu() -> String {
    cpu_of(&std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default())
}

fn cpu_of(cpuinfo: &str) -> String {
    cpu_model(cpuinfo).unwrap_or_else(|| std::env::consts::ARCH.to_owned())
}

/// `model name` of the first processor in `/proc/cpuinfo`.
fn cpu_model(cpuinfo: &str) -> Option<String> {
    cpuinfo
        .lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split_once(':'))
        .map(|(_, v)| v.trim().to_owned())
}

/// Distinct `(physical id, core id)` pairs in `/proc/cpuinfo`.
fn physical_cores(cpuinfo: &str) -> Option<usize> {
    let mut cores = std::collections::BTreeSet::new();
    let (mut package, mut core) = (None, None);
    for l in cpuinfo.lines().chain(std::iter::once("")) {
        let value = || l.split_once(':').map(|(_, v)| v.trim().to_owned());
        if l.starts_with("physical id") {
            package = value();
        } else if l.starts_with("core id") {
            core = value();
        } else if l.trim().is_empty()
            && let Some(c) = core.take()
        {
            cores.insert((package.take(), c));
        }
    }
    (!cores.is_empty()).then_some(cores.len())
}

fn memory_total() -> Option<String> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kib: u64 = meminfo
        .lines()
        .find(|l| l.starts_with("MemTotal:"))?
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()?;
    Some(format!("{:.1} GiB", kib as f64 / f64::from(1 << 20)))
}

fn os_name() -> String {
    let release = std::fs::read_to_string("/etc/os-release").unwrap_or_default();
    let pretty = release
        .lines()
        .find_map(|l| l.strip_prefix("PRETTY_NAME="))
        .map(|v| v.trim_matches('"').to_owned());
    let kernel = std::fs::read_to_string("/proc/sys/kernel/osrelease").ok();
    match (pretty, kernel) {
        (Some(os), Some(k)) => format!("{os}, kernel {}", k.trim()),
        (Some(os), None) => os,
        (None, _) => std::env::consts::OS.to_owned(),
    }
}

/// Now as `YYYY-MM-DD HH:MM:SS UTC`.
pub fn utc_now() -> String {
    utc(time::OffsetDateTime::now_utc())
}

/// `at` as `YYYY-MM-DD HH:MM:SS UTC`.
fn utc(at: time::OffsetDateTime) -> String {
    let at = at.to_offset(time::UtcOffset::UTC);
    format!(
        "{:04}-{:02}-{:02} {:02}:{:02}:{:02} UTC",
        at.year(),
        u8::from(at.month()),
        at.day(),
        at.hour(),
        at.minute(),
        at.second()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_from_day_counts() {
        let day = |days: i64| utc(time::OffsetDateTime::from_unix_timestamp(days * 86_400).unwrap());
        assert_eq!(day(0), "1970-01-01 00:00:00 UTC");
        assert_eq!(day(11_016), "2000-02-29 00:00:00 UTC");
        assert_eq!(day(20_787), "2026-11-30 00:00:00 UTC");
        let at = time::OffsetDateTime::from_unix_timestamp(20_787 * 86_400 + 3_723).unwrap();
        assert_eq!(utc(at), "2026-11-30 01:02:03 UTC");
    }

    #[test]
    fn cores_are_counted_once_per_physical_core() {
        let cpuinfo = "processor: 0\nphysical id: 0\ncore id: 0\n\nprocessor: 1\nphysical id: 0\ncore id: 0\n\n\
                       processor: 2\nphysical id: 0\ncore id: 1\n";
        assert_eq!(physical_cores(cpuinfo), Some(2));
        assert_eq!(
            cpu_model("model name\t: Some CPU @ 2GHz\n").as_deref(),
            Some("Some CPU @ 2GHz")
        );
    }

    #[test]
    fn the_report_names_the_machine_and_the_build() {
        let report = machine_report("kessler bench x.ron");
        for key in [
            "cpu:",
            "hardware threads:",
            "os:",
            "rustc:",
            "kessler:",
            "reference state hash:",
            "date:",
            "command: kessler bench x.ron",
        ] {
            assert!(report.contains(key), "{key} missing in\n{report}");
        }
    }
}

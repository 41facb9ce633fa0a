//! `kessler ensemble aggregate DIR`: the finished members' timelines
//! summed up per combination of settings and timeline row —
//! `DIR/aggregate.csv` with the number of members and the mean, median,
//! 5th and 95th percentile of the bodies, the shatters so far and the
//! kinetic energy — and the plot of the bodies (`DIR/bodies.svg`, `.png`).
//!
//! Percentiles interpolate linearly between the closest ranks (the
//! definition numpy and R use by default): of `n` sorted values `v₀ … vₙ₋₁`,
//! the `p`-th is `v[⌊h⌋] + (h − ⌊h⌋)(v[⌊h⌋+1] − v[⌊h⌋])` with `h = (n − 1)p/100`;
//! the median is the 50th.

use rayon::prelude::*;

use super::EnsembleError;
use super::folder::{EnsembleFolder, Record};
use super::plot::{Band, BodiesPlot};
use crate::input::{InputError, read_text};
use crate::output::{CsvTable, check_replaceable, commit_all, stage};
use crate::simulation::TimelineRow;

/// The mean, median, 5th and 95th percentile of some values.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// The mean.
    pub mean: f64,
    /// The median (the 50th percentile).
    pub median: f64,
    /// The 5th percentile.
    pub p5: f64,
    /// The 95th percentile.
    pub p95: f64,
}

/// The `p`-th percentile (0 to 100) of `sorted` (ascending, not empty),
/// interpolated linearly between the closest ranks.
pub fn percentile(sorted: &[f64], p: f64) -> f64 {
    let h = (sorted.len() - 1) as f64 * p / 100.0;
    let below = h.floor() as usize;
    let above = (below + 1).min(sorted.len() - 1);
    sorted[below] + (h - below as f64) * (sorted[above] - sorted[below])
}

impl Stats {
    /// The statistics of `values` (not empty), which it sorts.
    pub fn of(values: &mut [f64]) -> Self {
        values.sort_unstable_by(f64::total_cmp);
        Self {
            mean: values.iter().sum::<f64>() / values.len() as f64,
            median: percentile(values, 50.0),
            p5: percentile(values, 5.0),
            p95: percentile(values, 95.0),
        }
    }
}

/// One row of `aggregate.csv`: one combination at one timeline row.
#[derive(Clone, Debug, PartialEq)]
pub struct AggregateRow {
    /// The combination's index.
    pub combination: u64,
    /// The combination in words (`key=value ...`; empty when nothing is
    /// varied).
    pub settings: String,
    /// Updates run at the row.
    pub update: u64,
    /// Finished members of the combination.
    pub members: u64,
    /// Bodies.
    pub bodies: Stats,
    /// Shatters since the start.
    pub shatters: Stats,
    /// Kinetic energy.
    pub kinetic_energy: Stats,
}

// The columns (a stable contract) and cells of a row.
crate::csv_row!(AggregateRow, |r| {
    combination: r.combination,
    settings: &r.settings,
    update: r.update,
    members: r.members,
    bodies_mean: r.bodies.mean,
    bodies_median: r.bodies.median,
    bodies_p5: r.bodies.p5,
    bodies_p95: r.bodies.p95,
    shatters_mean: r.shatters.mean,
    shatters_median: r.shatters.median,
    shatters_p5: r.shatters.p5,
    shatters_p95: r.shatters.p95,
    kinetic_energy_mean: r.kinetic_energy.mean,
    kinetic_energy_median: r.kinetic_energy.median,
    kinetic_energy_p5: r.kinetic_energy.p5,
    kinetic_energy_p95: r.kinetic_energy.p95,
});

/// What one member's timeline says, by row.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    /// Updates at each row.
    pub update: Vec<u64>,
    /// Bodies.
    pub bodies: Vec<f64>,
    /// Shatters since the start.
    pub shatters: Vec<f64>,
    /// Kinetic energy.
    pub kinetic_energy: Vec<f64>,
}

/// Reads a member's timeline.
pub fn read_series(folder: &EnsembleFolder, index: u64) -> Result<Series, InputError> {
    let path = folder.timeline(index);
    let origin = path.display().to_string();
    let text = read_text(&path)?;
    let table = CsvTable::parse::<TimelineRow>(&text).map_err(|e| InputError::new(&origin, e))?;
    let column = |name: &str| -> Result<Vec<f64>, InputError> {
        table
            .column(name)
            .unwrap_or_default()
            .iter()
            .map(|cell| {
                cell.parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| {
                    InputError::new(&origin, format!("column `{name}`: `{cell}` is not a finite number"))
                })
            })
            .collect()
    };
    let mut shatters = column("shatters")?;
    let mut so_far = 0.0;
    for s in &mut shatters {
        so_far += *s;
        *s = so_far;
    }
    Ok(Series {
        update: column("update")?.into_iter().map(|u| u as u64).collect(),
        bodies: column("bodies")?,
        shatters,
        kinetic_energy: column("kinetic_energy")?,
    })
}

/// The rows of one combination from its members' series (all of one
/// length, not empty).
pub fn combination_rows(combination: u64, settings: &str, series: &[Series]) -> Vec<AggregateRow> {
    let rows = series[0].update.len();
    let mut values = vec![0.0; series.len()];
    let mut stats = |pick: &dyn Fn(&Series) -> f64| {
        for (value, s) in values.iter_mut().zip(series) {
            *value = pick(s);
        }
        Stats::of(&mut values)
    };
    (0..rows)
        .map(|r| AggregateRow {
            combination,
            settings: settings.to_owned(),
            update: series[0].update[r],
            members: series.len() as u64,
            bodies: stats(&|s| s.bodies[r]),
            shatters: stats(&|s| s.shatters[r]),
            kinetic_energy: stats(&|s| s.kinetic_energy[r]),
        })
        .collect()
}

/// What an aggregation found.
#[derive(Clone, Debug, PartialEq)]
pub struct Aggregated {
    /// Finished members summed up.
    pub members: u64,
    /// Combinations with at least one.
    pub combinations: u64,
    /// Rows written.
    pub rows: usize,
}

/// Sums up the members `done` (in ascending order, as a [`Census`](super::Census)
/// lists them) of the ensemble in `folder` and writes `aggregate.csv`
/// and the plot, all or none of them.
pub fn aggregate(folder: &EnsembleFolder, record: &Record, done: &[u64]) -> Result<Aggregated, EnsembleError> {
    // The output rule of every command: only regular files are replaced.
    for path in [folder.aggregate_csv(), folder.plot("svg"), folder.plot("png")] {
        check_replaceable("ensemble aggregate:", &path)?;
    }
    let config = &record.config;
    let series: Vec<Series> = done
        .par_iter()
        .map(|&index| read_series(folder, index))
        .collect::<Result<_, _>>()?;
    let mut rows = Vec::new();
    let mut bands = Vec::new();
    // A combination's members are neighbours in index order.
    let mut start = 0;
    while start < done.len() {
        let combination = config.place(done[start]).0;
        let end = start
            + done[start..]
                .iter()
                .take_while(|&&i| config.place(i).0 == combination)
                .count();
        let members = &series[start..end];
        if let Some(k) = members.iter().position(|s| s.update != members[0].update) {
            return Err(EnsembleError::Input(InputError::new(
                folder.timeline(done[start + k]).display().to_string(),
                "its rows are not those of the other members of its combination; run the member again (remove its folder and resume)",
            )));
        }
        start = end;
        let label = config.vary.label(combination);
        let these = combination_rows(combination, &label, members);
        bands.push(Band {
            label: if label.is_empty() {
                "the scenario's settings".to_owned()
            } else {
                label
            },
            members: members.len() as u64,
            update: these.iter().map(|r| r.update as f64).collect(),
            median: these.iter().map(|r| r.bodies.median).collect(),
            low: these.iter().map(|r| r.bodies.p5).collect(),
            high: these.iter().map(|r| r.bodies.p95).collect(),
        });
        rows.extend(these);
    }
    let title = format!(
        "{}: bodies over updates, median and 5–95 % band",
        std::path::Path::new(&record.scenario_source)
            .file_name()
            .map_or(record.scenario_source.clone(), |n| n.to_string_lossy().into_owned())
    );
    let plot = BodiesPlot {
        bands: &bands,
        title: &title,
    };
    let svg = plot.svg().map_err(|e| EnsembleError::Failed(e.to_string()))?;
    let png = plot.png().map_err(|e| EnsembleError::Failed(e.to_string()))?;
    let staged = vec![
        stage(&folder.aggregate_csv(), |w| crate::output::write_csv(w, &rows))?,
        stage(&folder.plot("svg"), |w| w.write_all(svg.as_bytes()))?,
        stage(&folder.plot("png"), |w| w.write_all(&png))?,
    ];
    commit_all(staged)?;
    Ok(Aggregated {
        members: done.len() as u64,
        combinations: bands.len() as u64,
        rows: rows.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_interpolate_between_the_closest_ranks() {
        let sorted = [1.0, 2.0, 4.0, 8.0, 16.0];
        // h = 4p/100: the 5th is 1 + 0.2·(2 − 1), the 95th 8 + 0.8·(16 − 8).
        let near = |a: f64, b: f64| (a - b).abs() < 1e-12;
        assert!(near(percentile(&sorted, 5.0), 1.2));
        assert_eq!(percentile(&sorted, 50.0), 4.0);
        assert!(near(percentile(&sorted, 95.0), 14.4));
        assert_eq!(percentile(&sorted, 0.0), 1.0);
        assert_eq!(percentile(&sorted, 100.0), 16.0);
        assert_eq!(percentile(&[3.0], 95.0), 3.0);
        let mut values = [4.0, 1.0, 3.0, 2.0];
        let stats = Stats::of(&mut values);
        // The median of four: halfway between the middle two.
        assert_eq!((stats.mean, stats.median), (2.5, 2.5));
        assert!((stats.p5 - 1.15).abs() < 1e-12 && (stats.p95 - 3.85).abs() < 1e-12);
    }

    #[test]
    fn a_combination_sums_up_its_members_row_by_row() {
        let member = |bodies: [f64; 2], shatters: [f64; 2]| Series {
            update: vec![0, 10],
            bodies: bodies.to_vec(),
            shatters: shatters.to_vec(),
            kinetic_energy: vec![1.0, 2.0],
        };
        let rows = combination_rows(
            3,
            "a=1",
            &[member([10.0, 12.0], [0.0, 1.0]), member([10.0, 20.0], [0.0, 5.0])],
        );
        assert_eq!(rows.len(), 2);
        assert_eq!((rows[1].combination, rows[1].update, rows[1].members), (3, 10, 2));
        assert_eq!(rows[1].bodies.mean, 16.0);
        assert_eq!(rows[1].bodies.p95, 12.0 + 0.95 * 8.0);
        assert_eq!(rows[1].shatters.median, 3.0);
        assert_eq!(rows[0].kinetic_energy.p5, 1.0);
    }
}

//! `kbc bench`: the planner's scaling ladder (see `crate::ladder`), as a table or JSON.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use clap::ValueEnum;

use super::plan::LookaheadArg;
use crate::ir::stn::{UNITS, format_time};
use crate::ladder::{self, Row, Rung};
use crate::planner::{Budget, SearchKind};
use crate::session::PlanSettings;

#[derive(clap::Args)]
pub(super) struct BenchArgs {
    /// Which searches to run on every rung.
    #[arg(long, value_enum, default_value_t = Searches::Both)]
    search: Searches,
    /// Only rungs whose name contains this text (e.g. `build`, `_b20_`).
    #[arg(long, value_name = "TEXT")]
    filter: Option<String>,
    /// The seed of the generated problems.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Seconds each heuristic search may take.
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0)]
    timeout: f64,
    /// Seconds each paper search may take.
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0)]
    paper_timeout: f64,
    /// The paper's depth limit (default: its own default, 25).
    #[arg(long, value_name = "N")]
    max_depth: Option<u32>,
    /// Write each rung's goal file into this directory instead of planning.
    #[arg(long, value_name = "DIR")]
    write: Option<PathBuf>,
    /// When the heuristic search follows relaxed plans ahead (as `kbc plan --lookahead`;
    /// `--lookahead` alone means `on`; `--lookahead=off` never).
    #[arg(long, value_enum, value_name = "WHEN", num_args = 0..=1, require_equals = true, default_value_t = LookaheadArg::Auto,
          default_missing_value = "on")]
    lookahead: LookaheadArg,
    /// After the first plan, go on searching for shorter makespans for this many seconds
    /// (as `kbc plan --improve`); the ratio column then shows what the improvement reached.
    #[arg(long, value_name = "SECONDS")]
    improve: Option<f64>,
    /// As `--improve`, for this many states expanded after the first plan instead of a time
    /// (as `kbc plan --improve-states`; not with `--improve`).
    #[arg(long, value_name = "N", default_value_t = 0, conflicts_with = "improve")]
    improve_states: u64,
    /// The output format.
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Searches {
    Both,
    Heuristic,
    Paper,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Format {
    Text,
    Json,
}

pub(super) fn run(args: BenchArgs) -> ExitCode {
    let rungs: Vec<Rung> = ladder::all()
        .into_iter()
        .map(|r| Rung { seed: args.seed, ..r })
        .filter(|r| args.filter.as_deref().is_none_or(|f| r.name().contains(f)))
        .collect();
    if rungs.is_empty() {
        eprintln!("error: no rung of the ladder matches `--filter`");
        eprintln!("note: rung names look like `build_b08_a3_s1`: family, blocks, arms, seed");
        return ExitCode::from(2);
    }
    if let Some(dir) = &args.write {
        return write_rungs(dir, &rungs);
    }
    if !(args.timeout > 0.0 && args.timeout.is_finite() && args.paper_timeout > 0.0 && args.paper_timeout.is_finite()) {
        eprintln!("error: timeouts must be positive numbers of seconds");
        return ExitCode::from(2);
    }
    let improve = match args.improve {
        None => None,
        Some(seconds) if seconds > 0.0 && seconds.is_finite() => Some(Duration::from_secs_f64(seconds)),
        Some(_) => {
            eprintln!("error: `--improve` takes a positive number of seconds");
            return ExitCode::from(2);
        }
    };
    let searches: &[SearchKind] = match args.search {
        Searches::Both => &[SearchKind::Heuristic, SearchKind::Paper],
        Searches::Heuristic => &[SearchKind::Heuristic],
        Searches::Paper => &[SearchKind::Paper],
    };
    let mut out = std::io::stdout().lock();
    if args.format == Format::Text {
        let _ = writeln!(
            out,
            "{:<20} {:<9} {:>7} {:>9} {:>9} {:>6} {:>7} {:>9} {:>9}  {:>9}  result",
            "problem", "search", "length", "makespan", "bound", "ratio", "speedup", "expanded", "seconds", "paper/heur"
        );
    }
    let mut rows: Vec<Row> = Vec::new();
    for rung in &rungs {
        let mut heuristic_time = None;
        for &search in searches {
            let seconds = if search == SearchKind::Paper { args.paper_timeout } else { args.timeout };
            let budget = Budget {
                max_states: u64::MAX,
                deadline: Some(Instant::now() + Duration::from_secs_f64(seconds)),
                ..Budget::default()
            };
            // (The paper's search has no improvement phase.)
            let improve = if search == SearchKind::Heuristic { improve } else { None };
            let improve_states = args.improve_states;
            let settings =
                PlanSettings { lookahead: args.lookahead.into(), improve, improve_states, ..PlanSettings::default() };
            let row = ladder::run_with(rung, search, budget, args.max_depth, &settings);
            if search == SearchKind::Heuristic && row.result.is_ok() {
                heuristic_time = Some(row.elapsed);
            }
            if args.format == Format::Text {
                let ratio = match (search, &row.result, heuristic_time) {
                    (SearchKind::Paper, Ok(_), Some(h)) => {
                        format!("{:.1}x", row.elapsed.as_secs_f64() / h.as_secs_f64().max(1e-9))
                    }
                    _ => String::new(),
                };
                let _ = writeln!(
                    out,
                    "{:<20} {:<9} {:>7} {:>9} {:>9} {:>6} {:>7} {:>9} {:>9.3}  {:>9}  {}",
                    rung.name(),
                    search_name(search),
                    row.result.as_ref().map_or("-".to_string(), |n| n.to_string()),
                    row.makespan.map_or("-".to_string(), |(m, _)| format_time(m)),
                    row.lower_bound.map_or("-".to_string(), |b| {
                        format!("{}{}", format_time(b.makespan), if b.optimal { "*" } else { "" })
                    }),
                    match (row.makespan, row.lower_bound) {
                        (Some((m, _)), Some(b)) if b.makespan > 0 => format!("{:.2}x", m as f64 / b.makespan as f64),
                        _ => "-".to_string(),
                    },
                    row.makespan.map_or("-".to_string(), |(m, s)| format!("{:.2}x", s as f64 / m.max(1) as f64)),
                    row.expanded,
                    row.elapsed.as_secs_f64(),
                    ratio,
                    match &row.result {
                        Ok(_) => "solved",
                        Err(why) => why,
                    }
                );
                let _ = out.flush();
            }
            rows.push(row);
        }
    }
    if args.format == Format::Text {
        for &search in searches {
            let _ = writeln!(out, "{}", summary(search, &rows));
        }
    }
    if args.format == Format::Json {
        let rows: Vec<serde_json::Value> = rows
            .iter()
            .map(|row| {
                serde_json::json!({
                    "problem": row.rung.name(),
                    "family": row.rung.family.name(),
                    "blocks": row.rung.blocks,
                    "arms": row.rung.arms,
                    "seed": row.rung.seed,
                    "search": search_name(row.search),
                    "solved": row.result.is_ok(),
                    "length": row.result.as_ref().ok(),
                    "failure": row.result.as_ref().err(),
                    "makespan": row.makespan.map(|(m, _)| m as f64 / UNITS as f64),
                    "sequential": row.makespan.map(|(_, s)| s as f64 / UNITS as f64),
                    "lower_bound": row.lower_bound.map(|b| serde_json::json!({
                        "makespan": b.makespan as f64 / UNITS as f64,
                        "work": b.work as f64 / UNITS as f64,
                        "block": b.block as f64 / UNITS as f64,
                        "chain": b.chain as f64 / UNITS as f64,
                        "aside": b.aside as f64 / UNITS as f64,
                        "waiting": b.waiting as f64 / UNITS as f64,
                        "emptying": b.emptying as f64 / UNITS as f64,
                        "searched": b.searched as f64 / UNITS as f64,
                        "optimal": b.optimal,
                        "idle": b.idle as f64 / UNITS as f64,
                    })),
                    "expanded": row.expanded,
                    "seconds": row.elapsed.as_secs_f64(),
                })
            })
            .collect();
        let _ = writeln!(out, "{}", serde_json::Value::Array(rows));
    }
    // A plan that fails validation is a planner bug: make it visible in the exit status.
    if rows.iter().any(|r| r.result.as_ref().is_err_and(|why| why.starts_with("INVALID"))) {
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}

/// One line on the rows of `search`: how many rungs it solved and how long the slowest
/// took, and on how many the makespan is within 1.3 and 1.15 times the bound (the ratios
/// unrounded, unlike the table's column), with the sum of the makespans.
fn summary(search: SearchKind, rows: &[Row]) -> String {
    let rows: Vec<&Row> = rows.iter().filter(|r| r.search == search).collect();
    let solved: Vec<&&Row> = rows.iter().filter(|r| r.result.is_ok()).collect();
    let slowest = rows
        .iter()
        .max_by_key(|r| r.elapsed)
        .map_or(String::new(), |r| format!(", slowest {} {:.3} s", r.rung.name(), r.elapsed.as_secs_f64()));
    // (makespan, bound) of the solved rungs.
    let pairs: Vec<(i64, i64)> = solved.iter().filter_map(|r| Some((r.makespan?.0, r.lower_bound?.makespan))).collect();
    // m <= f * b, with f in hundredths and exact integers.
    let within = |hundredths: i64| pairs.iter().filter(|&&(m, b)| b > 0 && m * 100 <= b * hundredths).count();
    let sum: i64 = pairs.iter().map(|&(m, _)| m).sum();
    // Rungs whose bound is the optimum (`*`), and those whose plan meets it (the separations
    // of its ordered snap actions, thousandths each, aside: under half a unit more).
    let optimal: Vec<&&Row> = solved.iter().copied().filter(|r| r.lower_bound.is_some_and(|b| b.optimal)).collect();
    let met = optimal
        .iter()
        .filter(|r| matches!((r.makespan, r.lower_bound), (Some((m, _)), Some(b)) if 2 * (m - b.makespan) < UNITS))
        .count();
    format!(
        "{} search: {} of {} rungs solved{slowest}; makespan within 1.3x of the bound on {}, within 1.15x on {}; \
         the bound is the optimum (*) on {}, met on {}; sum of makespans {}",
        search_name(search),
        solved.len(),
        rows.len(),
        within(130),
        within(115),
        optimal.len(),
        met,
        format_time(sum)
    )
}

fn search_name(search: SearchKind) -> &'static str {
    match search {
        SearchKind::Paper => "paper",
        SearchKind::Heuristic => "heuristic",
    }
}

fn write_rungs(dir: &std::path::Path, rungs: &[Rung]) -> ExitCode {
    if let Err(error) = std::fs::create_dir_all(dir) {
        eprintln!("error: cannot create `{}`: {error}", dir.display());
        return ExitCode::from(1);
    }
    for rung in rungs {
        let path = dir.join(format!("{}.pl", rung.name()));
        if let Err(error) = super::write_atomically(&path, rung.source().as_bytes()) {
            eprintln!("error: cannot write `{}`: {error}", path.display());
            return ExitCode::from(1);
        }
    }
    let files = if rungs.len() == 1 { "goal file" } else { "goal files" };
    super::status(&format!("wrote {} {files} to {}", rungs.len(), dir.display()));
    ExitCode::SUCCESS
}

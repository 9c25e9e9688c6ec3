//! `rbtrack cost`: the correlation-filter tracker's cost model ([`crate::cf64::cost`]): a
//! configuration's estimate, or the model against the instructions `examples/budget.rs`
//! counts in QEMU, row by row and stage by stage; with `--fit`, the costs per operation
//! that fit the rows best.

use super::args::CostArgs;
use super::{cf64_for, check_read, emit, fail, overrides, Failure, TrackerKind};
use crate::cf64::cost::{budget_row, fit, Operations, Target, PER_OPERATION, STAGES};
use serde::Serialize;
use std::collections::BTreeMap;
use std::io::Write;

/// Largest relative error the model may make on a row's stage or total.
const TOLERANCE: f64 = 0.10;

/// The scene's target is 54 px tall on the mean frame at scale 1 ([`Target::scene`]).
const SCENE_HEIGHT: f64 = 54.0;

/// One row of the budget example: what ran and the instructions counted per stage
/// (`None` where the row does not print the stage).
struct Row {
    label: String,
    operations: Operations,
    measured: [Option<f64>; 5],
    total: f64,
}

/// The estimate of one configuration, as `--json` prints it.
#[derive(Serialize)]
struct Estimate {
    target: Target,
    operations: Operations,
    stages: BTreeMap<&'static str, u64>,
    instructions: u64,
}

/// Runs `rbtrack cost`: the configuration's estimate; or, given the budget example's
/// output, each row's estimate against QEMU's count per stage, `Ok(false)` if any is off
/// by more than [`TOLERANCE`].
pub fn cost(args: &CostArgs, out: &mut dyn Write) -> Result<bool, Failure> {
    let Some(budget) = &args.budget else {
        return estimate(args, out).map(|()| true);
    };
    let text = std::fs::read_to_string(budget)
        .map_err(|e| fail(format!("cannot read {}: {e}", budget.display())))?;
    let rows = parse(&text);
    if rows.is_empty() {
        return Err(fail(format!(
            "{}: no correlation-filter rows of the budget example",
            budget.display()
        )));
    }
    let costs: Vec<Vec<f64>> = if args.fit {
        let fitted = (0..STAGES.len())
            .map(|i| {
                let stage: Vec<(Vec<f64>, f64)> = rows
                    .iter()
                    .filter_map(|r| Some((r.operations.terms()[i].clone(), r.measured[i]?)))
                    .collect();
                fit(&stage).ok_or_else(|| fail(format!("{}: the fit is singular", STAGES[i])))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut text = String::from("costs per operation (cf64::cost::PER_OPERATION):\n");
        for (name, c) in STAGES.iter().zip(&fitted) {
            let list: Vec<String> = c.iter().map(|v| format!("{v:.1}")).collect();
            text += &format!("{name:>9}: [{}]\n", list.join(", "));
        }
        emit(out, &(text + "\n"))?;
        fitted
    } else {
        PER_OPERATION.iter().map(|c| c.to_vec()).collect()
    };
    let costs: [&[f64]; 5] = std::array::from_fn(|i| costs[i].as_slice());
    let mut text = format!(
        "{:<31} {}   total (estimate / QEMU, error)\n",
        "row",
        STAGES.map(|s| format!("{s:>22}")).join(" ")
    );
    let mut worst: f64 = 0.0;
    for row in &rows {
        let estimate = row.operations.stages_by(&costs);
        text += &format!("{:<31}", row.label);
        for (e, m) in estimate.iter().zip(&row.measured) {
            text += &match m {
                Some(m) => {
                    worst = worst.max((e / m - 1.0).abs());
                    format!(
                        " {:>7.0}k/{:>7.0}k {:>+5.1}%",
                        e / 1e3,
                        m / 1e3,
                        100.0 * (e / m - 1.0)
                    )
                }
                None => format!(" {:>22}", "-"),
            };
        }
        let total: f64 = estimate.iter().sum();
        worst = worst.max((total / row.total - 1.0).abs());
        text += &format!(
            "   {:.0}k / {:.0}k {:+.1}%\n",
            total / 1e3,
            row.total / 1e3,
            100.0 * (total / row.total - 1.0)
        );
    }
    let within = worst <= TOLERANCE;
    text += &format!(
        "largest error {:.1} % ({} the {:.0} % allowed)\n",
        100.0 * worst,
        if within { "within" } else { "beyond" },
        100.0 * TOLERANCE
    );
    emit(out, &text)?;
    Ok(within)
}

/// Prints the estimate of `args`' configuration on the budget example's scene.
fn estimate(args: &CostArgs, out: &mut dyn Write) -> Result<(), Failure> {
    let overrides = overrides(&args.config)?;
    check_read(&overrides, &[TrackerKind::Cf64])?;
    let params = cf64_for(&overrides, TrackerKind::Cf64)?
        .ok_or_else(|| fail("no correlation-filter configuration"))?;
    let target = Target::scene(1.0);
    let operations = Operations::of(&params, target);
    let stages = operations.stages();
    if args.json {
        let doc = Estimate {
            target,
            operations,
            stages: STAGES
                .iter()
                .zip(stages)
                .map(|(&name, v)| (name, v.round() as u64))
                .collect(),
            instructions: operations.instructions(),
        };
        let text = serde_json::to_string(&doc).map_err(fail)?;
        return emit(out, &format!("{text}\n"));
    }
    let mut text = format!(
        "Cortex-M4 instructions a frame (cf64::cost), the budget example's scene (first box \
         {} x {} px, {} x {} px on the mean frame):\n",
        target.first.0, target.first.1, target.current.0, target.current.1
    );
    for (name, v) in STAGES.iter().zip(stages) {
        text += &format!("{name:>9} {:>10.0}\n", v);
    }
    text += &format!("{:>9} {:>10}\n", "total", operations.instructions());
    emit(out, &text)
}

/// The correlation-filter rows of the budget example's output: its configuration table
/// (`G S cell area ring size_of` then the five stages, the total, ..., the tracker's mean
/// box height) and its table against the target's size (`height`, the box's, then
/// `features scale total max`, the defaults).
fn parse(text: &str) -> Vec<Row> {
    let numbers = |line: &str| -> Option<Vec<f64>> {
        line.split_whitespace().map(|w| w.parse().ok()).collect()
    };
    let mut rows = Vec::new();
    let mut table = "";
    for line in text.lines() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("G  S cell area") {
            table = "configurations";
            continue;
        }
        if trimmed.starts_with("height  box h  features") {
            table = "sizes";
            continue;
        }
        let Some(v) = numbers(line).filter(|v| !v.is_empty()) else {
            table = if line.trim().is_empty() { "" } else { table };
            continue;
        };
        match (table, v.as_slice()) {
            (
                "configurations",
                &[g, s, cell, area, ring, _, f, fi, c, sc, l, total, _, _, _, box_h],
            ) => {
                let params = budget_row(
                    g as usize,
                    s as usize,
                    cell as usize,
                    area as u32,
                    ring as usize,
                );
                rows.push(Row {
                    label: format!("G {g} S {s} cell {cell} area {area} ring {ring}"),
                    operations: Operations::of(&params, Target::scene(1.0).tracked(box_h)),
                    measured: [f, fi, c, sc, l].map(Some),
                    total,
                });
            }
            ("sizes", &[height, box_h, f, sc, total, _]) => {
                let params = budget_row(16, 4, 4, 512, 2);
                let target = Target::scene(height / SCENE_HEIGHT).tracked(box_h);
                rows.push(Row {
                    label: format!("defaults, {height} px tall"),
                    operations: Operations::of(&params, target),
                    measured: [Some(f), None, None, Some(sc), None],
                    total,
                });
            }
            _ => {}
        }
    }
    rows
}

//! Instructions executed per function of an embedded binary, from a QEMU trace.
//!
//! Reads QEMU's `-d in_asm,exec,nochain` log on standard input (every translated block's
//! instructions once, then one `Trace` line per execution of a block) and an
//! `llvm-objdump -d` listing of the same binary, and prints the functions that executed the
//! most instructions over the run. `--annotate FILE` also writes the listing with each
//! instruction's execution count in front. The README's performance section shows the
//! commands (the log is large: stream it through a FIFO).
//!
//! ```sh
//! cargo run --release -p rbtrack-host --example qemu_profile -- LISTING [--annotate OUT] < LOG
//! ```

use std::collections::HashMap;
use std::io::{BufRead, Write};

/// Parses `0x0000abcd:` or `abcd:` at the start of `text`.
fn address(text: &str) -> Option<u32> {
    let text = text.trim_start();
    let text = text.strip_prefix("0x").unwrap_or(text);
    let (hex, _) = text.split_once(':')?;
    u32::from_str_radix(hex, 16).ok()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (listing, annotate) = match args.as_slice() {
        [listing] => (listing, None),
        [listing, flag, out] if flag == "--annotate" => (listing, Some(out)),
        _ => return Err("usage: qemu_profile LISTING [--annotate OUT] < QEMU_LOG".into()),
    };

    // Block start -> its instructions' addresses; block start -> executions.
    let mut blocks: HashMap<u32, Vec<u32>> = HashMap::new();
    let mut runs: HashMap<u32, u64> = HashMap::new();
    let mut current: Option<u32> = None;
    let mut translating = false;
    for line in std::io::stdin().lock().lines() {
        let line = line?;
        if line.starts_with("IN:") {
            (translating, current) = (true, None);
        } else if translating && line.starts_with("0x") {
            if let Some(a) = address(&line) {
                let start = *current.get_or_insert(a);
                let block = blocks.entry(start).or_default();
                if start == a {
                    block.clear(); // a block translated again
                }
                block.push(a);
            }
        } else if line.starts_with("Trace") {
            translating = false;
            // `Trace 0: 0x... [flags/pc/...]`: the block's guest pc is the second field.
            let pc = line
                .split_once('[')
                .and_then(|(_, rest)| rest.split('/').nth(1))
                .and_then(|pc| u32::from_str_radix(pc, 16).ok());
            if let Some(pc) = pc {
                *runs.entry(pc).or_default() += 1;
            }
        } else if line.starts_with('-') {
            translating = false;
        }
    }
    let mut executed: HashMap<u32, u64> = HashMap::new();
    for (start, n) in &runs {
        for a in blocks.get(start).into_iter().flatten() {
            *executed.entry(*a).or_default() += n;
        }
    }

    let text = std::fs::read_to_string(listing)?;
    let mut out = annotate.map(std::fs::File::create).transpose()?;
    let mut per_function: HashMap<&str, u64> = HashMap::new();
    let mut function = "?";
    for line in text.lines() {
        let count = if let Some(name) = line.strip_suffix(">:").and_then(|l| l.split_once(" <")) {
            function = name.1;
            None
        } else if line.starts_with(' ') {
            address(line).map(|a| executed.get(&a).copied().unwrap_or(0))
        } else {
            None
        };
        if let Some(n) = count {
            *per_function.entry(function).or_default() += n;
        }
        if let Some(out) = out.as_mut() {
            match count {
                Some(n) => writeln!(out, "{n:>12} {line}")?,
                None => writeln!(out, "{:>12} {line}", "")?,
            }
        }
    }
    let total: u64 = per_function.values().sum();
    let mut ranked: Vec<_> = per_function.into_iter().collect();
    ranked.sort_by_key(|&(_, n)| std::cmp::Reverse(n));
    println!("{total:>14} instructions executed in all");
    for (name, n) in ranked.iter().take(30) {
        let share = 100.0 * *n as f64 / total.max(1) as f64;
        println!("{n:>14} {share:5.1} %  {name}");
    }
    Ok(())
}

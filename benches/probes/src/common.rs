//! Probe framework: every probe runs in a child process (the binary re-invoked with
//! `--one NAME`) on a 2 MiB thread, with panics caught and a timeout, so one crash, abort or
//! hang does not stop the round.
#![allow(dead_code)]

use std::io::Read;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// (expected, got, pass)
pub type R = (String, String, bool);

pub struct Probe {
    pub class: &'static str,
    pub name: &'static str,
    pub what: &'static str,
    pub f: fn() -> R,
}

pub fn rel(a: f64, b: f64) -> f64 {
    if b == 0.0 { a.abs() } else { (a - b).abs() / b.abs() }
}

pub fn r(expected: impl Into<String>, got: impl Into<String>, ok: bool) -> R {
    (expected.into(), got.into(), ok)
}

fn esc(s: &str) -> String {
    s.replace('\t', " ").replace('\n', " ⏎ ")
}

pub fn main_with(probes: Vec<Probe>) {
    let args: Vec<String> = std::env::args().collect();
    if args.len() >= 3 && args[1] == "--one" {
        let p = probes.iter().find(|p| p.name == args[2]).expect("no such probe");
        let f = p.f;
        let h = std::thread::Builder::new()
            .stack_size(2 << 20)
            .spawn(move || std::panic::catch_unwind(f))
            .expect("thread")
            .join();
        match h {
            Ok(Ok((e, g, ok))) => println!(
                "RESULT\t{}\t{}\t{}",
                if ok { "PASS" } else { "FAIL" },
                esc(&e),
                esc(&g)
            ),
            Ok(Err(payload)) => {
                let msg = payload
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                println!("RESULT\tPANIC\t\t{}", esc(&msg));
            }
            Err(_) => println!("RESULT\tPANIC\t\tthread join failed"),
        }
        return;
    }
    let filter: Vec<String> = args[1..].to_vec();
    let timeout: u64 = std::env::var("PROBE_TIMEOUT").ok().and_then(|s| s.parse().ok()).unwrap_or(180);
    let exe = std::env::current_exe().unwrap();
    let mut counts = std::collections::BTreeMap::<String, usize>::new();
    for p in &probes {
        if !filter.is_empty() && !filter.iter().any(|f| p.name.contains(f.as_str()) || p.class == f) {
            continue;
        }
        let start = Instant::now();
        let mut child = Command::new(&exe)
            .args(["--one", p.name])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut status = None;
        while start.elapsed() < Duration::from_secs(timeout) {
            if let Some(s) = child.try_wait().unwrap() {
                status = Some(s);
                break;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let mut out = String::new();
        let mut err = String::new();
        let line = match status {
            None => {
                let _ = child.kill();
                let _ = child.wait();
                format!("TIMEOUT\t\tno answer after {timeout} s")
            }
            Some(s) => {
                child.stdout.take().unwrap().read_to_string(&mut out).ok();
                child.stderr.take().unwrap().read_to_string(&mut err).ok();
                match out.lines().find(|l| l.starts_with("RESULT\t")) {
                    Some(l) => {
                        let l = l.trim_start_matches("RESULT\t").to_string();
                        if l.starts_with("PANIC") {
                            format!("{l} | stderr: {}", esc(err.lines().find(|x| x.contains("panicked")).unwrap_or("")))
                        } else {
                            l
                        }
                    }
                    None => format!(
                        "CRASH\t\tchild died ({s}); stderr tail: {}",
                        esc(&err.lines().rev().take(3).collect::<Vec<_>>().join(" | "))
                    ),
                }
            }
        };
        let verdict = line.split('\t').next().unwrap_or("").to_string();
        *counts.entry(verdict).or_default() += 1;
        println!(
            "{}\t{}\t{}\t{}\t{:.1}s",
            p.class,
            p.name,
            p.what,
            line,
            start.elapsed().as_secs_f64()
        );
    }
    eprintln!("summary: {counts:?}");
}

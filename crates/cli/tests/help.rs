//! `--help` of every subcommand succeeds and describes each of its flags: the flags each
//! subcommand must offer are listed here (from its `Args`), and every option line of the help
//! has a description; every flag that takes a value states its default.

use std::process::Command;

const SUBCOMMANDS: &[(&str, &[&str])] = &[
    (
        "run",
        &[
            "--out",
            "--t-end",
            "--snapshots",
            "--quiet",
            "--checkpoint-every",
            "--resume",
            "--force",
            "--max-output",
        ],
    ),
    (
        "demo",
        &[
            "--table",
            "--t-max",
            "--accuracy",
            "--svg",
            "--out",
            "--quick",
            "--size",
            "--quiet",
        ],
    ),
    (
        "query",
        &[
            "--against",
            "--out",
            "--accuracy",
            "--t-max",
            "--geometry",
            "--chunk-rows",
        ],
    ),
    (
        "accuracy",
        &["--cases", "--seed", "--out", "--svg", "--force"],
    ),
    ("bench", &["--quick", "--json", "--sim", "--edmd"]),
    (
        "render",
        &[
            "--out", "--frame", "--scene", "--format", "--view", "--size",
        ],
    ),
];

/// The help's option entries: the flag, whether it takes a value, and its description
/// (continuation lines included).
fn options(help: &str) -> Vec<(String, bool, String)> {
    let mut out: Vec<(String, bool, String)> = Vec::new();
    let mut in_options = false;
    for line in help.lines() {
        if line.starts_with("Options:") {
            in_options = true;
            continue;
        }
        if !in_options {
            continue;
        }
        let trimmed = line.trim_start();
        if trimmed.starts_with("--") || trimmed.starts_with("-h,") {
            let flag_part = trimmed.trim_start_matches("-h, ");
            let (head, description) = flag_part
                .split_once("  ")
                .map_or((flag_part, ""), |(h, d)| (h, d.trim()));
            let flag = head.split_whitespace().next().unwrap_or("").to_string();
            out.push((flag, head.contains('<'), description.to_string()));
        } else if let Some(last) = out.last_mut()
            && !trimmed.is_empty()
            && line.starts_with(' ')
        {
            last.2.push(' ');
            last.2.push_str(trimmed);
        } else if !line.starts_with(' ') && !line.is_empty() {
            in_options = false;
        }
    }
    out
}

#[test]
fn every_subcommand_describes_every_flag() {
    for &(command, flags) in SUBCOMMANDS {
        let out = Command::new(env!("CARGO_BIN_EXE_spheresweep"))
            .args([command, "--help"])
            .output()
            .unwrap();
        assert!(out.status.success(), "{command} --help failed");
        let help = String::from_utf8(out.stdout).unwrap();
        let entries = options(&help);
        for flag in flags {
            assert!(
                entries.iter().any(|(f, _, _)| f == flag),
                "`{command} --help` does not list {flag}:\n{help}"
            );
        }
        for (flag, takes_value, description) in entries.iter().filter(|e| e.0 != "--help") {
            assert!(
                description.split_whitespace().count() >= 3,
                "`{command} --help`: {flag} has no description"
            );
            if *takes_value {
                assert!(
                    description.to_lowercase().contains("default"),
                    "`{command} --help`: {flag} does not state its default: {description}"
                );
            }
        }
    }
}

//! The register of claims as docs/results.md shows it, and `tetwalk verify`'s lines.

use crate::engine::verify::{CheckResult, Expect, REGISTER, Verified};

/// The register as a markdown table, generated from [`REGISTER`] (docs/results.md holds it verbatim).
pub fn register_table() -> String {
    let mut out = String::from(
        "| method | the claim, quoted | verdict | smallest counterexample we know | `tetwalk verify` checks |\n|---|---|---|---|---|\n",
    );
    for e in REGISTER {
        let checks = if e.checks.is_empty() {
            "-".to_string()
        } else {
            e.checks
                .iter()
                .map(|c| format!("`{}`", c.name))
                .collect::<Vec<_>>()
                .join(", ")
        };
        out += &format!(
            "| {} | {} | {} | {} | {checks} |\n",
            e.methods, e.claim, e.verdict, e.counterexample
        );
    }
    out
}

/// One check's line: PASS when the claim held, FAIL when it was refuted; and whether that is what the
/// register says.
pub(crate) fn line(c: &CheckResult) -> String {
    let word = |holds: bool| if holds { "stands" } else { "refuted" };
    let register = match (c.as_registered, c.expect) {
        (Some(true), _) => "as registered".to_string(),
        (Some(false), e) => format!(
            "AGAINST THE REGISTER, which says {}",
            word(e == Expect::Stands)
        ),
        (None, _) => format!(
            "registered for {}; {} compiles differently",
            c.registered_for.unwrap_or("another adapter"),
            c.backend
        ),
    };
    format!(
        "{}  {:<26} {}, {register}: {}",
        if c.holds { "PASS" } else { "FAIL" },
        c.name,
        word(c.holds),
        c.seen
    )
}

/// A picked check's line: [`line()`] where it ran, `SKIP` and why where it did not.
pub(crate) fn verified_line(v: &Verified) -> String {
    match v {
        Verified::Checked(c) => line(c),
        Verified::Skipped { name, why } => format!("SKIP  {name:<26} {why}"),
    }
}

/// The checks run, those that hold, are refuted and skipped, and which go against the register.
pub(crate) fn summary(all: &[Verified]) -> String {
    let done: Vec<&CheckResult> = all.iter().filter_map(Verified::checked).collect();
    let against = against(all);
    format!(
        "{} claims checked, {} stand, {} refuted, {} skipped; {}",
        done.len(),
        done.iter().filter(|c| c.holds).count(),
        done.iter().filter(|c| !c.holds).count(),
        all.len() - done.len(),
        if against.is_empty() {
            "every one as the register says".to_string()
        } else {
            format!("against the register: {}", against.join(", "))
        }
    )
}

/// The checks whose result is not what the register says.
pub(crate) fn against(all: &[Verified]) -> Vec<&'static str> {
    all.iter()
        .filter_map(Verified::checked)
        .filter(|c| c.as_registered == Some(false))
        .map(|c| c.name)
        .collect()
}

//! `tetwalk methods`'s table: every registered method, its family, its claim, whether it runs on a
//! GPU, and what it implements.

use crate::family::Listed;

/// The methods as a markdown table.
pub(crate) fn table(rows: &[Listed]) -> String {
    let mut s = String::from(
        "| method | family | claims robust | GPU | implements |\n|---|---|---|---|---|\n",
    );
    for r in rows {
        let claims = match (r.reference, r.claims_robust) {
            (true, _) => "reference",
            (false, true) => "yes",
            (false, false) => "no",
        };
        s += &format!(
            "| {} | {} | {claims} | {} | {} |\n",
            r.name, r.family, r.gpu, r.implements
        );
    }
    s
}

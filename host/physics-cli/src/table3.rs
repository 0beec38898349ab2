//! `vphys table3`.

use anyhow::Result;
use virtual_physics::measure::table3::{measure, Measured};

fn ns(m: &Measured) -> String {
    m.ns.map_or("-".into(), |x| format!("{x:.1}"))
}

pub fn run(json: bool, timed: bool) -> Result<()> {
    let t = measure(timed);
    if json {
        outln!("{}", serde_json::to_string(&t)?);
        return Ok(());
    }
    outln!(
        "{:<22} | {:>17} {:>8} | {:>17} {:>8} | {:>17} {:>17}",
        "",
        "geometric (ours)",
        "",
        "matrix (ours)",
        "",
        "paper geometric",
        "paper matrix"
    );
    outln!(
        "{:<22} | {:>8} {:>8} {:>8} | {:>8} {:>8} {:>8} | {:>8} {:>8} {:>8} {:>8}",
        "operation",
        "×",
        "+",
        "ns",
        "×",
        "+",
        "ns",
        "×",
        "+",
        "×",
        "+"
    );
    outln!("{}", "-".repeat(120));
    for r in &t.rows {
        let div = |m: &Measured| {
            if m.div > 0 {
                format!("{}×+{}÷", m.mul, m.div)
            } else {
                m.mul.to_string()
            }
        };
        outln!(
            "{:<22} | {:>8} {:>8} {:>8} | {:>8} {:>8} {:>8} | {:>8} {:>8} {:>8} {:>8}",
            r.op,
            div(&r.geometric),
            r.geometric.add,
            ns(&r.geometric),
            div(&r.matrix),
            r.matrix.add,
            ns(&r.matrix),
            r.paper.geometric.mul,
            r.paper.geometric.add,
            r.paper.matrix.mul,
            r.paper.matrix.add
        );
    }
    outln!(
        "\ncounts: measured by running the same generic code on a counting scalar; \
         ns: f64, best of 7 loops of ~10 ms with black_box."
    );
    Ok(())
}

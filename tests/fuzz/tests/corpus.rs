//! The committed corpora, replayed in this process (no fuzzing): every input runs
//! without a panic, every `valid-*` seed is accepted, and every seed the project's
//! encoders make today is committed (and, if `valid-*`, accepted).

use foosball_fuzz::runner::load_corpus;
use foosball_fuzz::{corpus_dir, seeds, Verdict, TARGETS};

#[test]
fn every_target_has_a_corpus_with_accepted_seeds() {
    for target in &TARGETS {
        let corpus = load_corpus(&corpus_dir(target.name)).expect("the corpus folder is readable");
        assert!(
            corpus.len() >= 3,
            "{}: only {} corpus inputs",
            target.name,
            corpus.len()
        );
        let mut accepted = 0;
        for (path, bytes) in &corpus {
            let verdict = (target.run)(bytes);
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
            if name.starts_with("valid-") {
                assert_eq!(
                    verdict,
                    Verdict::Accepted,
                    "{}: {} is not accepted",
                    target.name,
                    path.display()
                );
            }
            accepted += usize::from(verdict == Verdict::Accepted);
        }
        assert!(accepted > 0, "{}: no corpus input is accepted", target.name);
    }
}

#[test]
fn generated_seeds_are_in_the_corpus() {
    for target in &TARGETS {
        let corpus = load_corpus(&corpus_dir(target.name)).expect("the corpus folder is readable");
        for (name, bytes) in seeds::seeds(target.name) {
            let committed = corpus
                .iter()
                .any(|(path, _)| path.file_name().and_then(|n| n.to_str()) == Some(&name));
            assert!(
                committed,
                "{}: seed {name} is not committed; run `cargo run -p foosball-fuzz -- seed-corpus`",
                target.name
            );
            if name.starts_with("valid-") {
                assert!(
                    (target.run)(&bytes) == Verdict::Accepted,
                    "{}: today's {name} is not accepted",
                    target.name
                );
            }
        }
    }
}

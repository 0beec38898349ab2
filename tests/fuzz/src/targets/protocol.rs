//! USB reports: decode, and an accepted report encodes back to the same bytes.

use super::Verdict;
use foosball_protocol::{InReport, OutReport};

pub(super) fn in_report(input: &[u8]) -> Verdict {
    match InReport::decode(input) {
        Ok(report) => {
            assert_eq!(
                report.to_bytes()[..],
                *input,
                "IN report does not round-trip"
            );
            Verdict::Accepted
        }
        Err(_) => Verdict::Rejected,
    }
}

pub(super) fn out_report(input: &[u8]) -> Verdict {
    match OutReport::decode(input) {
        Ok(report) => {
            assert_eq!(
                report.to_bytes()[..],
                *input,
                "OUT report does not round-trip"
            );
            Verdict::Accepted
        }
        Err(_) => Verdict::Rejected,
    }
}

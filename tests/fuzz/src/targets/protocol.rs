//! USB reports: decode, and an accepted report encodes back to the same bytes.

use super::Verdict;
use foosball_protocol::{decode_in_report, InReport, InReportV2, OutReport, PacketAge};

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

/// Either IN report version through `decode_in_report`: an accepted report encodes
/// back to the same bytes with its own version's encoder, and a v2 packet age reads
/// back in whole steps.
pub(super) fn in_report_any(input: &[u8]) -> Verdict {
    match decode_in_report(input) {
        Ok((report, None)) => {
            assert_eq!(
                report.to_bytes()[..],
                *input,
                "v1 IN report does not round-trip"
            );
            Verdict::Accepted
        }
        Ok((report, Some(timing))) => {
            let v2 = InReportV2 { report, timing };
            assert_eq!(
                v2.to_bytes()[..],
                *input,
                "v2 IN report does not round-trip"
            );
            assert_eq!(
                InReportV2::decode(input),
                Ok(v2),
                "the two v2 decoders agree"
            );
            for t in &timing.paddles {
                let age = t.newest_packet_age;
                match age.as_micros() {
                    None => assert_eq!(age, PacketAge::NONE),
                    Some(us) => assert_eq!(PacketAge::from_micros(u64::from(us)), age),
                }
            }
            Verdict::Accepted
        }
        Err(_) => Verdict::Rejected,
    }
}

//! Feature reports: both decoders on arbitrary bytes. Each input is refused with a
//! named error or taken as a report that encodes back to the same bytes; the board's
//! decoder (`decode_command`) takes exactly the host-written kinds that `decode` takes.

use super::Verdict;
use foosball_protocol::{DecodeError, FeatureReport, FEATURE_REPORT_LEN};

pub(super) fn run(input: &[u8]) -> Verdict {
    let full = FeatureReport::decode(input);
    let command = FeatureReport::decode_command(input);
    match (&full, &command) {
        (Ok(report), Ok(from_command)) => {
            assert_eq!(report, from_command, "the two decoders agree");
            assert!(
                !report.kind().is_board_only(),
                "decode_command took a board-only kind: {report:?}"
            );
        }
        (Ok(report), Err(err)) => {
            assert!(
                report.kind().is_board_only(),
                "decode_command refused a host kind {report:?}: {err:?}"
            );
            assert!(
                matches!(err, DecodeError::BadField { field: "kind", .. }),
                "a board-only kind is refused as its kind, not {err:?}"
            );
        }
        (Err(err), Ok(report)) => {
            panic!("decode refused {report:?}, which decode_command took: {err:?}")
        }
        (Err(full_err), Err(command_err)) => {
            // Kind-independent checks come first, so both name the same problem,
            // unless the kind is board-only.
            if !matches!(command_err, DecodeError::BadField { field: "kind", .. }) {
                assert_eq!(
                    full_err, command_err,
                    "the two decoders name the same error"
                );
            }
            return Verdict::Rejected;
        }
    }
    let report = full.unwrap_or_else(|_| unreachable!("accepted above"));
    assert_eq!(input.len(), FEATURE_REPORT_LEN);
    assert_eq!(
        report.to_bytes()[..],
        *input,
        "Feature report does not re-encode to the same bytes"
    );
    let mut buf = [0u8; FEATURE_REPORT_LEN + 8];
    assert_eq!(report.encode(&mut buf), Ok(FEATURE_REPORT_LEN));
    assert_eq!(
        buf[..FEATURE_REPORT_LEN],
        *input,
        "encode agrees with to_bytes"
    );
    Verdict::Accepted
}

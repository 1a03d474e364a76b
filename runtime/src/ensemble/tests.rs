use super::*;

/// The progress line shows the time elapsed and the time left, and indicatif takes it.
#[cfg(feature = "progress")]
#[test]
fn progress_shows_elapsed_and_eta() {
    assert!(PROGRESS_TEMPLATE.contains("{elapsed_precise}"));
    assert!(PROGRESS_TEMPLATE.contains("{eta_precise}"));
    assert!(indicatif::ProgressStyle::with_template(PROGRESS_TEMPLATE).is_ok());
}

fn results(
    params: Vec<Params>,
    results: Vec<Result<Vec<f64>, SimulationError>>,
) -> Results<Vec<f64>> {
    Results {
        index: (0..params.len()).collect(),
        params,
        results,
        columns: vec!["x".to_string(), "y, z".to_string()],
    }
}

fn temp(name: &str) -> std::path::PathBuf {
    std::env::temp_dir()
        .join(format!("lagrange-results-{}", std::process::id()))
        .join(name)
}

/// Members with different parameter names get a column per name in first-seen order, empty
/// where a member lacks it; names with commas or quotes are quoted as RFC 4180 says; missing
/// folders are created.
#[test]
fn csv_has_a_column_per_parameter_name_quoted() {
    let r = results(
        vec![
            vec![("a", 1.0), ("b,c", 2.0)],
            vec![("d\"q", 3.0), ("a", 4.0)],
        ],
        vec![
            Ok(vec![5.0, 6.0]),
            Err(SimulationError::InvalidOptions {
                message: "said \"no\"\nthen".to_string(),
            }),
        ],
    );
    let path = temp("nested/deeper/sweep.csv");
    let _ = std::fs::remove_dir_all(temp(""));
    r.write_csv(&path, true).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "member,a,\"b,c\",\"d\"\"q\",x,\"y, z\",error");
    // Counts as integers, not 1e0 (spreadsheets read both, people only the first).
    assert_eq!(lines[1], "0,1,2,,5,6,");
    assert!(lines[2].starts_with("1,4,,3,,,\""), "{}", lines[2]);
    assert!(lines[2].contains("said \"\"no\"\" then"), "{}", lines[2]);
    assert_eq!(lines.len(), 3);
    // A shard without its header has the same columns.
    r.write_csv(&path, false).unwrap();
    let shard = std::fs::read_to_string(&path).unwrap();
    assert_eq!(
        shard,
        lines[1..]
            .iter()
            .map(|l| format!("{l}\n"))
            .collect::<String>()
    );
    let _ = std::fs::remove_dir_all(temp(""));
}

/// CSV numbers: integers as integers, others as the shortest decimal that reads back to the
/// same f64, in exponent form only far from 1.
#[test]
fn csv_numbers_read_back_exactly() {
    for (v, text) in [
        (19.0, "19"),
        (-3.0, "-3"),
        (2.006066806131417, "2.006066806131417"),
        (0.000125, "0.000125"),
        (1e-20, "1e-20"),
        (6.02e23, "6.02e23"),
        (0.0, "0"),
    ] {
        assert_eq!(super::results::csv_number(v), text);
        assert_eq!(text.parse::<f64>().unwrap(), v);
    }
    assert_eq!(super::results::csv_number(f64::NAN), "NaN");
}

/// A reduction that returned fewer or more values than its columns is refused with
/// InvalidInput naming the member and the counts, and nothing is written.
#[test]
fn csv_refuses_a_row_of_the_wrong_length() {
    for vals in [vec![1.0], vec![1.0, 2.0, 3.0]] {
        let n = vals.len();
        let r = results(vec![vec![], vec![]], vec![Ok(vec![1.0, 2.0]), Ok(vals)]);
        let path = temp(&format!("ragged{n}.csv"));
        let e = r.write_csv(&path, true).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
        let msg = e.to_string();
        assert!(
            msg.contains("member 1") && msg.contains(&format!("{n} values for 2 columns")),
            "{msg}"
        );
        assert!(!path.exists());
    }
}

/// A full disk (ENOSPC) names the path.
#[cfg(target_os = "linux")]
#[test]
fn csv_names_the_path_on_a_full_disk() {
    let r = results(vec![vec![("a", 1.0)]], vec![Ok(vec![1.0, 2.0])]);
    let e = r.write_csv("/dev/full", true).unwrap_err();
    assert!(e.to_string().contains("/dev/full"), "{e}");
}

/// A member naming a parameter twice is refused (one column per name would lose a value).
#[test]
fn csv_refuses_a_parameter_named_twice() {
    let r = results(vec![vec![("a", 1.0), ("a", 2.0)]], vec![Ok(vec![1.0, 2.0])]);
    let e = r.write_csv(temp("twice.csv"), true).unwrap_err();
    assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
    assert!(e.to_string().contains("member 0"), "{e}");
}

//! Which seeds an ensemble runs: `--seeds 100..200` (end excluded), `100..=199`, lists
//! `1,5,7` and mixes `1,5,10..20`, so that one ensemble can be split across machines by seed
//! ranges and merged afterwards.

use crate::options::OptionError;

/// The seeds of `spec`, in the order given, each once; every seed fits a TOML integer (i64).
pub fn parse_seeds(spec: &str) -> Result<Vec<u64>, OptionError> {
    let wrong = |problem: String| OptionError::new("--seeds", spec, problem);
    let mut seeds = Vec::new();
    for part in spec.split(',').map(str::trim) {
        if part.is_empty() {
            return Err(wrong("an empty item".into()));
        }
        let (first, last) = match (part.split_once("..="), part.split_once("..")) {
            (Some((a, b)), _) => (number(a, spec)?, number(b, spec)?),
            (None, Some((a, b))) => {
                let (a, b) = (number(a, spec)?, number(b, spec)?);
                if b <= a {
                    return Err(wrong(format!("the range {part} is empty")));
                }
                (a, b - 1)
            }
            (None, None) => (number(part, spec)?, number(part, spec)?),
        };
        if last < first {
            return Err(wrong(format!("the range {part} is empty")));
        }
        if last - first >= 10_000_000 {
            return Err(wrong(format!("{part} names more than 10 million seeds")));
        }
        seeds.extend(first..=last);
    }
    let mut seen = std::collections::BTreeSet::new();
    seeds.retain(|s| seen.insert(*s));
    Ok(seeds)
}

/// `n` seeds from `first` on (`--n`).
pub fn first_n(first: u64, n: usize) -> Result<Vec<u64>, OptionError> {
    if n == 0 {
        return Err(OptionError::new("--n", n, "must be at least 1"));
    }
    let last = first.checked_add(n as u64 - 1).filter(|l| i64::try_from(*l).is_ok());
    match last {
        Some(last) => Ok((first..=last).collect()),
        None => Err(OptionError::new(
            "--n",
            n,
            format!("seeds from {first} on pass the largest seed {}", i64::MAX),
        )),
    }
}

fn number(text: &str, spec: &str) -> Result<u64, OptionError> {
    text.trim().parse::<u64>().ok().filter(|v| i64::try_from(*v).is_ok()).ok_or_else(|| {
        OptionError::new("--seeds", spec, format!("\"{}\" is not a seed (0 … {})", text.trim(), i64::MAX))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_lists_and_mixes() {
        assert_eq!(parse_seeds("100..104").unwrap(), [100, 101, 102, 103]);
        assert_eq!(parse_seeds("3..=5").unwrap(), [3, 4, 5]);
        assert_eq!(parse_seeds("7, 1,5").unwrap(), [7, 1, 5]);
        assert_eq!(parse_seeds("1,5,4..7,5").unwrap(), [1, 5, 4, 6]);
        assert_eq!(first_n(10, 3).unwrap(), [10, 11, 12]);
    }

    #[test]
    fn bad_specs_say_what_is_wrong() {
        for (spec, needle) in [
            ("5..5", "empty"),
            ("5..=4", "empty"),
            ("a..3", "\"a\" is not a seed"),
            ("1,,2", "empty item"),
            ("-3", "not a seed"),
            ("9223372036854775808", "not a seed"),
            ("0..20000000", "more than 10 million"),
        ] {
            let e = parse_seeds(spec).unwrap_err();
            assert!(e.to_string().contains(needle), "{spec}: {e}");
        }
        assert!(first_n(0, 0).is_err());
        assert!(first_n(i64::MAX as u64, 2).unwrap_err().to_string().contains("largest seed"));
    }
}

//! `shadelab cache`: the compile store of [`crate::isa::store`]: where it is, its entries and
//! size (per family with `--verify`, which reads and checks every entry), and its pruning:
//! everything (`--prune`) or the least recently used entries down to a size (`--max-size`).
use std::collections::BTreeMap;
use std::process::ExitCode;

use clap::Args;

use crate::error::{Error, Result};
use crate::isa::store::{self, Store};

#[derive(Args, Debug)]
pub(super) struct CacheArgs {
    /// Read every entry and check it (checksum, length, key); a corrupt one is removed.
    /// Lists the entries per family.
    #[arg(long)]
    verify: bool,
    /// Remove every entry.
    #[arg(long, conflicts_with = "max_size")]
    prune: bool,
    /// Remove the least recently used entries until the store holds at most SIZE (bytes, or
    /// with a K, M or G suffix: 500M). Without it the store keeps itself under 2G.
    #[arg(long, value_name = "SIZE", value_parser = parse_bytes)]
    max_size: Option<u64>,
}

/// "500M" as bytes (K, M, G: powers of 1024).
fn parse_bytes(s: &str) -> std::result::Result<u64, String> {
    let t = s.trim();
    let (num, mult) = match t.chars().last().map(|c| c.to_ascii_uppercase()) {
        Some('K') => (&t[..t.len() - 1], 1u64 << 10),
        Some('M') => (&t[..t.len() - 1], 1 << 20),
        Some('G') => (&t[..t.len() - 1], 1 << 30),
        _ => (t, 1),
    };
    num.trim()
        .parse::<u64>()
        .ok()
        .and_then(|n| n.checked_mul(mult))
        .ok_or_else(|| format!("`{s}` is not a size: bytes, or a number with K, M or G (500M)"))
}

/// Bytes as "12.3 MB".
fn mb(bytes: u64) -> String {
    format!("{:.1} MB", bytes as f64 / 1e6)
}

pub(super) fn cmd_cache(a: &CacheArgs) -> Result<ExitCode> {
    let dir = store::default_dir().ok_or_else(|| {
        Error::Usage(
            "no cache folder: set XDG_CACHE_HOME or HOME (or SHADELAB_STORE to the store)".into(),
        )
    })?;
    let s = Store::at(&dir);
    // Entries that were to go and are still there (a read-only store): said, and exit 2.
    let mut kept = 0;
    let mut say_kept = |list: &[(std::path::PathBuf, String)]| {
        for (p, e) in list {
            eprintln!("shadelab: could not remove {}: {e}", p.display());
        }
        kept += list.len();
    };
    if a.prune {
        let done = s.prune_to(0)?;
        say_kept(&done.kept);
        println!(
            "{}: removed {} entries ({}){}",
            dir.display(),
            done.removed,
            mb(done.freed),
            not_removed(done.kept.len())
        );
    } else if let Some(max) = a.max_size {
        let done = s.prune_to(max)?;
        say_kept(&done.kept);
        println!(
            "{}: removed {} least recently used entries ({}) to stay under {}{}",
            dir.display(),
            done.removed,
            mb(done.freed),
            mb(max),
            not_removed(done.kept.len())
        );
    }
    if a.verify {
        let v = s.verify()?;
        for (p, why) in &v.removed {
            println!("removed {}: {why}", p.display());
        }
        for (p, why, e) in &v.kept {
            println!("not an entry, NOT removed {}: {why}", p.display());
            eprintln!("shadelab: could not remove {}: {e}", p.display());
        }
        kept += v.kept.len();
        let mut per: BTreeMap<String, usize> = BTreeMap::new();
        for e in &v.sound {
            *per.entry(e.material.family().to_string()).or_default() += 1;
        }
        for (family, n) in &per {
            println!("  {family}: {n}");
        }
        println!(
            "{} sound, {} removed{}",
            v.sound.len(),
            v.removed.len(),
            not_removed(v.kept.len())
        );
    }
    let entries = s.entries()?;
    let total: u64 = entries.iter().map(|e| e.size).sum();
    println!(
        "{}: {} entries, {}",
        dir.display(),
        entries.len(),
        mb(total)
    );
    if kept > 0 {
        return Err(Error::Output {
            what: format!("the compile store {}", dir.display()),
            message: format!(
                "{kept} entries could not be removed (is it read-only?): make the folder \
                 writable, or point SHADELAB_STORE at another"
            ),
        });
    }
    Ok(ExitCode::SUCCESS)
}

/// ", N could not be removed" when N > 0.
fn not_removed(n: usize) -> String {
    if n == 0 {
        String::new()
    } else {
        format!(", {n} could not be removed")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_their_suffix() {
        assert_eq!(parse_bytes("500M"), Ok(500 << 20));
        assert_eq!(parse_bytes("2g"), Ok(2 << 30));
        assert_eq!(parse_bytes("123"), Ok(123));
        for bad in ["", "M", "1.5G", "-1", "99999999999999999999G"] {
            assert!(parse_bytes(bad).is_err(), "{bad}");
        }
    }
}

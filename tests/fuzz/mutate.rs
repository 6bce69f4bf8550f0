//! Inputs for the fuzz engine: the seed files whole, then mutants of seeds, of excerpts of big
//! seeds, and of inputs the reader accepted (a small pool, so mutations pile up on inputs that
//! reach past the first checks), plus a few inputs built from scratch.
//!
//! Mutations know about text, not about one format: lines (delete, duplicate, swap, splice in a
//! line of another seed, repeat up to 1000 times), tokens (replace with a word seen in any seed,
//! delete), numbers (replace with an extreme: NaN, inf, 1e308, -0, subnormals, integers at the
//! i32/u32/i64/u64 edges, empty, unicode digits; or nudge an integer by one, which turns a
//! valid index into one past the end), bytes (flip, overwrite, insert, delete), truncation and
//! splicing two inputs. For OBJ, big files are cut into excerpts that stay valid: a random run
//! of faces with just the vertices, normals and texture coordinates they use, renumbered, in the
//! file's own index style.
use std::collections::HashSet;
use std::path::PathBuf;

use super::{Seeds, Syntax, Target};

/// Inputs are capped at this size (mutants that grow past it are cut).
const MAX_INPUT: usize = 64 << 10;
/// Seeds larger than this are excerpted before mutating (parsing the whole 2.4 MB bunny a
/// million times would take hours); each is still tried whole once.
const EXCERPT_ABOVE: usize = 16 << 10;
const POOL_SIZE: usize = 256;

/// Numbers that break readers: non-finite, f32/f64 range edges, subnormals, signed zero,
/// integer type edges, and things that only look like numbers.
const EXTREMES: &[&str] = &[
    "NaN",
    "nan",
    "-nan",
    "inf",
    "-inf",
    "+inf",
    "infinity",
    "1e308",
    "-1e308",
    "1.8e308",
    "1e39",
    "3.4028236e38",
    "-3.4028235e38",
    "1e-45",
    "1e-46",
    "4.9e-324",
    "-0",
    "-0.0",
    "0",
    "1",
    "-1",
    "2",
    "3",
    "4",
    "5",
    "7",
    "8",
    "255",
    "256",
    "16384",
    "16385",
    "65535",
    "65536",
    "2147483647",
    "2147483648",
    "-2147483648",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "9223372036854775808",
    "-9223372036854775808",
    "18446744073709551615",
    "18446744073709551616",
    "99999999999999999999999999999",
    "1e19",
    "0x10",
    "1_000",
    "0b1",
    "1.",
    "-.5",
    ".",
    "-",
    "+",
    "e5",
    "1e",
    "",
    "\u{663}",
    "\u{ff11}",
    "1\u{0}",
    "١e٣",
];

/// Short strings that break tokenizers: quotes, brackets, separators, line ends, control
/// characters, non-ASCII.
const INSERTS: &[&str] = &[
    "\"",
    "'",
    "[",
    "]",
    "[[",
    "]]",
    "{",
    "}",
    "=",
    ",",
    ".",
    "#",
    "/",
    "//",
    "///",
    "\\",
    "\n",
    "\r\n",
    "\r",
    "\t",
    " ",
    "\u{0}",
    "\u{feff}",
    "é",
    "\u{1f600}",
    "\u{202e}",
    "\"\"\"",
    "'''",
    "\\u0000",
    "\\x",
    "=[",
    " = ",
    "[mesh]",
    "[[light]]",
    "v 0 0 0\n",
    "f 1 2 3\n",
    "vn 0 0 1\n",
    // glTF buffer URIs: traversal, %-encoded traversal, absolute paths, schemes.
    "../",
    "..%2F",
    "%2E%2E/",
    "/dev/zero",
    "file:",
];

/// Where an input came from, for reports.
#[derive(Debug, Clone, Copy)]
pub enum Origin {
    Whole(usize),
    Mutant { base: Base, mutations: u32 },
    Random,
}

#[derive(Debug, Clone, Copy)]
pub enum Base {
    Seed(usize),
    Excerpt(usize),
    Pool,
}

struct Seed {
    name: String,
    bytes: Vec<u8>,
    obj: Option<ObjIndex>,
}

pub struct Mutator {
    rng: fastrand::Rng,
    seeds: Vec<Seed>,
    words: Vec<Vec<u8>>,
    pool: Vec<Vec<u8>>,
    /// Seeds still to be tried whole (the first inputs of a run).
    whole: usize,
}

/// The seed files of `seeds`, sorted by path (missing folders give none).
pub fn seed_files(seeds: &[Seeds]) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for s in seeds {
        let (dir, ext) = match *s {
            Seeds::Repo(dir, ext) => (PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(dir), ext),
            Seeds::Env(var, ext) => match std::env::var_os(var) {
                Some(d) if !d.is_empty() => (PathBuf::from(d), ext),
                _ => continue,
            },
        };
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        let mut found: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == ext))
            .collect();
        found.sort();
        files.extend(found);
    }
    files
}

impl Mutator {
    pub fn new(target: &Target, seed: u64) -> Self {
        let mut seeds = Vec::new();
        for path in seed_files(target.seeds) {
            let Ok(bytes) = std::fs::read(&path) else {
                continue;
            };
            let obj = (target.syntax == Syntax::Obj && bytes.len() > EXCERPT_ABOVE)
                .then(|| ObjIndex::new(&bytes));
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            seeds.push(Seed { name, bytes, obj });
        }
        assert!(!seeds.is_empty(), "target {}: no seed files", target.name);
        let mut words = HashSet::new();
        for s in &seeds {
            for w in s.bytes[..s.bytes.len().min(EXCERPT_ABOVE)].split(|b| b.is_ascii_whitespace())
            {
                if !w.is_empty() && w.len() <= 40 && words.len() < 4000 {
                    words.insert(w.to_vec());
                }
            }
        }
        let mut words: Vec<Vec<u8>> = words.into_iter().collect();
        words.sort();
        Mutator {
            rng: fastrand::Rng::with_seed(seed),
            whole: seeds.len(),
            seeds,
            words,
            pool: Vec::new(),
        }
    }

    /// Offers an input the reader accepted to the pool.
    pub fn accepted(&mut self, input: &[u8]) {
        if self.pool.len() < POOL_SIZE {
            self.pool.push(input.to_vec());
        } else if self.rng.u32(0..8) == 0 {
            let i = self.rng.usize(0..POOL_SIZE);
            self.pool[i].clear();
            self.pool[i].extend_from_slice(input);
        }
    }

    pub fn describe(&self, origin: &Origin) -> String {
        match *origin {
            Origin::Whole(i) => format!("{} whole", self.seeds[i].name),
            Origin::Random => "built from scratch".into(),
            Origin::Mutant { base, mutations } => {
                let base = match base {
                    Base::Seed(i) => self.seeds[i].name.clone(),
                    Base::Excerpt(i) => format!("an excerpt of {}", self.seeds[i].name),
                    Base::Pool => "an accepted input".into(),
                };
                format!("{base} with {mutations} mutations")
            }
        }
    }

    /// Writes the next input into `out`.
    pub fn next(&mut self, out: &mut Vec<u8>) -> Origin {
        out.clear();
        if self.whole > 0 {
            let i = self.seeds.len() - self.whole;
            self.whole -= 1;
            out.extend_from_slice(&self.seeds[i].bytes);
            return Origin::Whole(i);
        }
        if self.rng.u32(0..100) < 3 {
            self.scratch(out);
            return Origin::Random;
        }
        let base = if !self.pool.is_empty() && self.rng.bool() {
            let i = self.rng.usize(0..self.pool.len());
            out.extend_from_slice(&self.pool[i]);
            Base::Pool
        } else {
            let i = self.rng.usize(0..self.seeds.len());
            let seed = &self.seeds[i];
            if seed.bytes.len() <= EXCERPT_ABOVE {
                out.extend_from_slice(&seed.bytes);
                Base::Seed(i)
            } else {
                match &seed.obj {
                    Some(index) => index.excerpt(&seed.bytes, &mut self.rng, out),
                    None => line_window(&seed.bytes, &mut self.rng, out),
                }
                Base::Excerpt(i)
            }
        };
        // Mostly few mutations (stay close to valid, reach deep), sometimes many.
        let mutations = match self.rng.u32(0..10) {
            0..=4 => 1,
            5..=7 => self.rng.u32(2..5),
            _ => self.rng.u32(5..17),
        };
        for _ in 0..mutations {
            self.mutate(out);
        }
        out.truncate(MAX_INPUT);
        Origin::Mutant { base, mutations }
    }

    /// Lines of words seen in the seeds, extremes and separators.
    fn scratch(&mut self, out: &mut Vec<u8>) {
        if self.rng.u32(0..4) == 0 {
            let n = self.rng.usize(0..256);
            out.extend((0..n).map(|_| self.rng.u8(..)));
            return;
        }
        for _ in 0..self.rng.usize(1..40) {
            for k in 0..self.rng.usize(1..7) {
                if k > 0 {
                    out.push(b' ');
                }
                match self.rng.u32(0..4) {
                    0 => out.extend_from_slice(self.pick(EXTREMES).as_bytes()),
                    1 => out.extend_from_slice(self.pick(INSERTS).as_bytes()),
                    _ => {
                        let w = self.rng.usize(0..self.words.len());
                        out.extend_from_slice(&self.words[w]);
                    }
                }
            }
            out.push(b'\n');
        }
    }

    fn pick<'a>(&mut self, list: &[&'a str]) -> &'a str {
        list[self.rng.usize(0..list.len())]
    }

    /// A line of some seed (or pooled input).
    fn foreign_line(&mut self) -> Vec<u8> {
        let source: &[u8] = if !self.pool.is_empty() && self.rng.bool() {
            &self.pool[self.rng.usize(0..self.pool.len())]
        } else {
            let s = &self.seeds[self.rng.usize(0..self.seeds.len())].bytes;
            &s[..s.len().min(EXCERPT_ABOVE)]
        };
        if source.is_empty() {
            return Vec::new();
        }
        let (a, b) = line_at(source, self.rng.usize(0..source.len()));
        let mut line = source[a..b].to_vec();
        line.push(b'\n');
        line
    }

    fn mutate(&mut self, buf: &mut Vec<u8>) {
        if buf.is_empty() {
            buf.extend_from_slice(self.pick(INSERTS).as_bytes());
            return;
        }
        let at = self.rng.usize(0..buf.len());
        match self.rng.u32(0..100) {
            // Numbers: the most productive (counts, indices, sizes, coordinates).
            0..=24 => {
                if let Some((a, b)) = number_from(buf, at) {
                    let new = self.pick(EXTREMES);
                    buf.splice(a..b, new.bytes());
                }
            }
            25..=34 => {
                if let Some((a, b)) = number_from(buf, at) {
                    let nudged = std::str::from_utf8(&buf[a..b])
                        .ok()
                        .and_then(|s| s.parse::<i64>().ok())
                        .map(|n| n.saturating_add(self.rng.i64(-2..=2)));
                    let new = match nudged {
                        Some(n) => n.to_string(),
                        None => self.rng.i64(-1000..1000).to_string(),
                    };
                    buf.splice(a..b, new.bytes());
                }
            }
            // Tokens.
            35..=44 => {
                let (a, b) = token_at(buf, at);
                let w = self.words[self.rng.usize(0..self.words.len())].clone();
                buf.splice(a..b, w);
            }
            45..=48 => {
                let (a, b) = token_at(buf, at);
                buf.drain(a..b);
            }
            // Lines.
            49..=53 => {
                let (a, b) = line_at(buf, at);
                let end = (b + 1).min(buf.len());
                buf.drain(a..end);
            }
            54..=58 => {
                let (a, b) = line_at(buf, at);
                let mut line = buf[a..b].to_vec();
                line.push(b'\n');
                buf.splice(a..a, line);
            }
            59..=61 => {
                let (a, b) = line_at(buf, at);
                let mut line = buf[a..b].to_vec();
                line.push(b'\n');
                let times = self.rng.usize(2..1000).min(MAX_INPUT / line.len().max(1));
                let repeated = line.repeat(times);
                buf.splice(a..a, repeated);
            }
            62..=65 => {
                let (a1, b1) = line_at(buf, at);
                let (a2, b2) = line_at(buf, self.rng.usize(0..buf.len()));
                if b1 < a2 {
                    let second = buf[a2..b2].to_vec();
                    let first = buf[a1..b1].to_vec();
                    buf.splice(a2..b2, first);
                    buf.splice(a1..b1, second);
                }
            }
            66..=73 => {
                let (a, _) = line_at(buf, at);
                let line = self.foreign_line();
                buf.splice(a..a, line);
            }
            // Short inserts.
            74..=80 => {
                let s = self.pick(INSERTS);
                buf.splice(at..at, s.bytes());
            }
            // Bytes.
            81..=84 => buf[at] ^= 1 << self.rng.u32(0..8),
            85..=87 => buf[at] = self.rng.u8(..),
            88..=89 => buf.insert(at, self.rng.u8(..)),
            90..=92 => {
                let end = (at + self.rng.usize(1..16)).min(buf.len());
                buf.drain(at..end);
            }
            // Whole-input cuts and splices.
            93..=95 => buf.truncate(at),
            _ => {
                let other: Vec<u8> = if !self.pool.is_empty() && self.rng.bool() {
                    self.pool[self.rng.usize(0..self.pool.len())].clone()
                } else {
                    let s = &self.seeds[self.rng.usize(0..self.seeds.len())].bytes;
                    s[..s.len().min(EXCERPT_ABOVE)].to_vec()
                };
                if !other.is_empty() {
                    let from = self.rng.usize(0..other.len());
                    buf.truncate(at);
                    buf.extend_from_slice(&other[from..]);
                }
            }
        }
        buf.truncate(MAX_INPUT);
    }
}

/// The line containing byte `at`, without its '\n'.
fn line_at(buf: &[u8], at: usize) -> (usize, usize) {
    let at = at.min(buf.len());
    let a = buf[..at]
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |p| p + 1);
    let b = buf[at..]
        .iter()
        .position(|&b| b == b'\n')
        .map_or(buf.len(), |p| at + p);
    (a, b)
}

/// The whitespace-separated token containing or following byte `at`.
fn token_at(buf: &[u8], at: usize) -> (usize, usize) {
    let mut a = at;
    while a > 0 && !buf[a - 1].is_ascii_whitespace() {
        a -= 1;
    }
    let mut b = at;
    while b < buf.len() && !buf[b].is_ascii_whitespace() {
        b += 1;
    }
    (a, b)
}

/// The first number at or after byte `at` (wrapping around): a run of digits with its sign,
/// point and exponent, not inside a word.
fn number_from(buf: &[u8], at: usize) -> Option<(usize, usize)> {
    let n = buf.len();
    let is_start = |i: usize| {
        buf[i].is_ascii_digit()
            && (i == 0 || !(buf[i - 1].is_ascii_alphanumeric() || buf[i - 1] == b'_'))
    };
    let start = (at..n).chain(0..at).find(|&i| is_start(i))?;
    let mut a = start;
    while a > 0 && matches!(buf[a - 1], b'-' | b'+' | b'.') {
        a -= 1;
    }
    let mut b = start;
    while b < n
        && (buf[b].is_ascii_digit()
            || buf[b] == b'.'
            || ((buf[b] == b'e' || buf[b] == b'E') && b + 1 < n)
            || ((buf[b] == b'-' || buf[b] == b'+') && matches!(buf[b - 1], b'e' | b'E')))
    {
        b += 1;
    }
    Some((a, b))
}

/// A window of up to 60 lines of a big non-OBJ seed.
fn line_window(bytes: &[u8], rng: &mut fastrand::Rng, out: &mut Vec<u8>) {
    let (a, _) = line_at(bytes, rng.usize(0..bytes.len()));
    let mut end = a;
    for _ in 0..rng.usize(1..60) {
        match bytes[end..].iter().position(|&b| b == b'\n') {
            Some(p) => end += p + 1,
            None => {
                end = bytes.len();
                break;
            }
        }
    }
    out.extend_from_slice(&bytes[a..end]);
}

/// Where the statements of a big OBJ seed are, for excerpts.
struct ObjIndex {
    /// Byte ranges of the `v`, `vt`, `vn` lines, in file order per kind.
    v: Vec<(usize, usize)>,
    vt: Vec<(usize, usize)>,
    vn: Vec<(usize, usize)>,
    /// Byte range of each `f` line and the counts of v, vt, vn defined before it (for
    /// relative indices).
    f: Vec<((usize, usize), [usize; 3])>,
}

impl ObjIndex {
    fn new(bytes: &[u8]) -> Self {
        let mut index = ObjIndex {
            v: Vec::new(),
            vt: Vec::new(),
            vn: Vec::new(),
            f: Vec::new(),
        };
        let mut a = 0;
        while a < bytes.len() {
            let b = bytes[a..]
                .iter()
                .position(|&c| c == b'\n')
                .map_or(bytes.len(), |p| a + p);
            let line = &bytes[a..b];
            if line.starts_with(b"v ") {
                index.v.push((a, b));
            } else if line.starts_with(b"vt ") {
                index.vt.push((a, b));
            } else if line.starts_with(b"vn ") {
                index.vn.push((a, b));
            } else if line.starts_with(b"f ") {
                let counts = [index.v.len(), index.vt.len(), index.vn.len()];
                index.f.push(((a, b), counts));
            }
            a = b + 1;
        }
        index
    }

    /// A run of 1 to 40 faces with the elements they use, renumbered from 1 in order of first
    /// use; positive indices stay positive, relative ones stay relative.
    fn excerpt(&self, bytes: &[u8], rng: &mut fastrand::Rng, out: &mut Vec<u8>) {
        if self.f.is_empty() {
            return line_window(bytes, rng, out);
        }
        let len = rng.usize(1..=40).min(self.f.len());
        let first = rng.usize(0..=self.f.len() - len);
        let mut used: [Vec<usize>; 3] = Default::default();
        let mut faces = Vec::new();
        for &((a, b), counts) in &self.f[first..first + len] {
            let text = std::str::from_utf8(&bytes[a..b]).unwrap_or("");
            let mut face = Vec::new();
            for corner in text.split_whitespace().skip(1) {
                let mut parts = Vec::new();
                for (k, raw) in corner.split('/').take(3).enumerate() {
                    let resolved = raw.parse::<i64>().ok().and_then(|i| {
                        let i = if i < 0 { counts[k] as i64 + i } else { i - 1 };
                        usize::try_from(i).ok()
                    });
                    parts.push(resolved.map(|i| {
                        let pos = used[k].iter().position(|&u| u == i).unwrap_or_else(|| {
                            used[k].push(i);
                            used[k].len() - 1
                        });
                        (pos, raw.starts_with('-'))
                    }));
                }
                face.push(parts);
            }
            faces.push(face);
        }
        let lists = [&self.v, &self.vt, &self.vn];
        for k in [0, 1, 2] {
            for &i in &used[k] {
                if let Some(&(a, b)) = lists[k].get(i) {
                    out.extend_from_slice(&bytes[a..b]);
                    out.push(b'\n');
                }
            }
        }
        for face in faces {
            out.push(b'f');
            for corner in face {
                out.push(b' ');
                for (k, part) in corner.iter().enumerate() {
                    if k > 0 {
                        out.push(b'/');
                    }
                    if let Some((pos, relative)) = part {
                        let n = if *relative {
                            *pos as i64 - used[k].len() as i64
                        } else {
                            *pos as i64 + 1
                        };
                        out.extend_from_slice(n.to_string().as_bytes());
                    }
                }
            }
            out.push(b'\n');
        }
    }
}

//! The published figures and where they come from: `docs/figures.json` holds one entry per
//! figure that README.md and docs/*.md publish — its value, unit, the command that measures it,
//! the commit and machine it was measured on, and the date — and the pages mark each such
//! number with its id, written right after it as an HTML comment: `6.6<!--fig:demo.speedup-->×`
//! (GitHub shows `6.6×`).
//!
//! [`check`] finds every marked number and verifies that it is its entry's value as the entry
//! prints it, that every entry is published, that each commit is in the current history and that
//! no figure of the README predates a change to the code it measures (the entry's `code` paths).
//! [`refresh`] re-runs the commands (each once), reads each figure from the command's JSON on
//! standard output, rewrites the entries at the current commit and the marked numbers in the
//! pages. `tools/figures` runs both.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{json, Value};

/// The file of figures, relative to the repository's root.
pub const FIGURES: &str = "docs/figures.json";

/// The marker that follows a published number: `<!--fig:ID-->`.
const OPEN: &str = "<!--fig:";
const CLOSE: &str = "-->";

/// One published figure, as `docs/figures.json` holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// Its name, used by the pages' markers.
    pub id: String,
    /// The value, rounded to `digits` decimals.
    pub value: f64,
    /// Its unit as the pages write it (`s`, `%`, `×`, `lights`, …).
    pub unit: String,
    /// Decimals printed.
    pub digits: usize,
    /// The shell command (run from the repository's root) whose standard output is JSON.
    pub command: String,
    /// Where the figure is in that JSON: a dotted path (`sets.1.build_seconds`), or two such
    /// paths divided (`a.seconds / b.seconds`).
    pub json: String,
    /// The factor from the JSON's value to the published one (100 for a fraction as a percent).
    pub scale: f64,
    /// The commit measured (the whole hash).
    pub commit: String,
    /// The machine: `{ "cores": N, "cpu": "…" }`.
    pub machine: Value,
    /// The day it was measured, `YYYY-MM-DD`.
    pub date: String,
    /// The paths of the workspace's code it measures (crates' sources, the CLI's files): a
    /// change to them after `commit` makes it stale. Dependencies' updates (`Cargo.lock`) are
    /// not tracked.
    pub code: Vec<String>,
}

impl Figure {
    /// The value as the pages print it: `digits` decimals.
    #[must_use]
    pub fn printed(&self) -> String {
        format!("{:.*}", self.digits, self.value)
    }

    fn from_json(v: &Value) -> Result<Figure, String> {
        let id = v["id"].as_str().unwrap_or("(no id)").to_string();
        let text = |k: &str| {
            v[k].as_str()
                .map(str::to_string)
                .ok_or_else(|| format!("{FIGURES}: {id}: `{k}` is not a string"))
        };
        let number = |k: &str| {
            v[k].as_f64()
                .ok_or_else(|| format!("{FIGURES}: {id}: `{k}` is not a number"))
        };
        let machine = v["machine"].clone();
        if machine["cores"].as_u64().is_none() || machine["cpu"].as_str().is_none() {
            return Err(format!(
                "{FIGURES}: {id}: `machine` needs `cores` and `cpu`"
            ));
        }
        let code = v["code"]
            .as_array()
            .ok_or_else(|| format!("{FIGURES}: {id}: `code` is not a list of paths"))?
            .iter()
            .map(|p| p.as_str().map(str::to_string))
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| format!("{FIGURES}: {id}: `code` is not a list of paths"))?;
        Ok(Figure {
            value: number("value")?,
            unit: text("unit")?,
            digits: v["digits"].as_u64().unwrap_or(0) as usize,
            command: text("command")?,
            json: text("json")?,
            scale: v["scale"].as_f64().unwrap_or(1.0),
            commit: text("commit")?,
            machine,
            date: text("date")?,
            code,
            id,
        })
    }

    fn to_json(&self) -> Value {
        let mut v = json!({
            "id": self.id,
            "value": self.value,
            "unit": self.unit,
            "digits": self.digits,
            "command": self.command,
            "json": self.json,
            "commit": self.commit,
            "machine": self.machine,
            "date": self.date,
            "code": self.code,
        });
        if self.scale != 1.0 {
            v["scale"] = json!(self.scale);
        }
        v
    }
}

/// Reads `docs/figures.json` under `root`.
pub fn load(root: &Path) -> Result<Vec<Figure>, String> {
    let path = root.join(FIGURES);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let v: Value = serde_json::from_str(&text).map_err(|e| format!("{FIGURES}: {e}"))?;
    let list = v["figures"]
        .as_array()
        .ok_or_else(|| format!("{FIGURES}: no `figures` list"))?;
    let figures = list
        .iter()
        .map(Figure::from_json)
        .collect::<Result<Vec<_>, _>>()?;
    let mut seen = BTreeMap::new();
    for f in &figures {
        if seen.insert(f.id.as_str(), ()).is_some() {
            return Err(format!("{FIGURES}: {} is there twice", f.id));
        }
    }
    Ok(figures)
}

/// Writes `figures` to `docs/figures.json` whole: a temporary file renamed over it.
fn save(root: &Path, figures: &[Figure]) -> Result<(), String> {
    let v = json!({
        "about": "Every figure README.md and docs/*.md publish, each marked there with \
                  <!--fig:ID--> after the number. `tools/figures check` verifies them; \
                  `tools/figures refresh [ID …]` measures them again at the current commit.",
        "figures": figures.iter().map(Figure::to_json).collect::<Vec<_>>(),
    });
    let text = serde_json::to_string_pretty(&v).map_err(|e| e.to_string())? + "\n";
    write_whole(&root.join(FIGURES), &text)
}

/// Writes `text` to `path` whole (lgh-image's atomic write: a temporary file renamed over it).
fn write_whole(path: &Path, text: &str) -> Result<(), String> {
    lgh_image::write_atomic(path, |w| w.write_all(text.as_bytes()))
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// A marked number on a page.
#[derive(Debug, PartialEq)]
pub struct Mark {
    /// The figure's id.
    pub id: String,
    /// The number as written (thousands separators kept).
    pub written: String,
    /// Its byte range in the page.
    pub range: std::ops::Range<usize>,
    /// Its line, from 1.
    pub line: usize,
}

/// The marked numbers of a page: each `<!--fig:ID-->` and the number right before it (digits,
/// `.`, `,` and a leading `-` or `−`; empty when there is none).
#[must_use]
pub fn marks(page: &str) -> Vec<Mark> {
    let mut found = Vec::new();
    for (at, _) in page.match_indices(OPEN) {
        let rest = &page[at + OPEN.len()..];
        let id = rest.split(CLOSE).next().unwrap_or("").trim().to_string();
        let before = &page[..at];
        let start = before
            .char_indices()
            .rev()
            .take_while(|&(_, c)| c.is_ascii_digit() || c == '.' || c == ',')
            .last()
            .map_or(at, |(i, _)| i);
        let start = match before[..start].chars().next_back() {
            Some(c @ ('-' | '−')) => start - c.len_utf8(),
            _ => start,
        };
        found.push(Mark {
            id,
            written: page[start..at].to_string(),
            range: start..at,
            line: before.matches('\n').count() + 1,
        });
    }
    found
}

/// The pages that publish figures: README.md and docs/*.md, sorted.
#[must_use]
pub fn pages(root: &Path) -> Vec<PathBuf> {
    let mut pages = vec![root.join("README.md")];
    if let Ok(dir) = std::fs::read_dir(root.join("docs")) {
        let mut docs: Vec<PathBuf> = dir
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "md"))
            .collect();
        docs.sort();
        pages.extend(docs);
    }
    pages
}

/// `written` read as the number it shows: separators dropped, `−` as `-`.
fn plain(written: &str) -> String {
    written.replace(',', "").replace('−', "-")
}

fn git(root: &Path, args: &[&str]) -> Result<String, String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(root)
        .output()
        .map_err(|e| format!("git: {e}"))?;
    if out.status.success() {
        Ok(String::from_utf8_lossy(&out.stdout).trim().to_string())
    } else {
        let err = String::from_utf8_lossy(&out.stderr);
        Err(format!("git {}: {}", args.join(" "), err.trim()))
    }
}

/// Whether `root`'s clone has its whole history (a shallow clone cannot tell a commit's
/// ancestry).
fn whole_history(root: &Path) -> Result<bool, String> {
    Ok(git(root, &["rev-parse", "--is-shallow-repository"])? == "false")
}

/// Every problem with the published figures under `root`, one line each (empty: all is well).
/// Without the whole history (a shallow clone) the commits are not checked, which it says on
/// standard error.
pub fn check(root: &Path) -> Result<Vec<String>, String> {
    let figures = load(root)?;
    let by_id: BTreeMap<&str, &Figure> = figures.iter().map(|f| (f.id.as_str(), f)).collect();
    let mut problems = Vec::new();
    let mut published: BTreeMap<&str, Vec<String>> = BTreeMap::new();
    for page in pages(root) {
        let name = page
            .strip_prefix(root)
            .unwrap_or(&page)
            .display()
            .to_string();
        let text = std::fs::read_to_string(&page).map_err(|e| format!("{name}: {e}"))?;
        for m in marks(&text) {
            let at = format!("{name}:{}", m.line);
            match by_id.get(m.id.as_str()) {
                None => problems.push(format!("{at}: {} is not in {FIGURES}", m.id)),
                Some(f) if plain(&m.written) != f.printed() => problems.push(format!(
                    "{at}: {} is written {:?}; {FIGURES} has {} {}",
                    m.id,
                    m.written,
                    f.printed(),
                    f.unit
                )),
                Some(f) => published
                    .entry(f.id.as_str())
                    .or_default()
                    .push(name.clone()),
            }
        }
    }
    for f in &figures {
        if !published.contains_key(f.id.as_str()) {
            problems.push(format!("{FIGURES}: {} is published nowhere", f.id));
        }
    }
    if !whole_history(root)? {
        eprintln!("figures: a shallow clone: the commits were not checked");
        return Ok(problems);
    }
    for f in &figures {
        if git(root, &["merge-base", "--is-ancestor", &f.commit, "HEAD"]).is_err() {
            problems.push(format!(
                "{}: commit {} is not in this history",
                f.id, f.commit
            ));
            continue;
        }
        let pages = published.get(f.id.as_str());
        let in_readme = pages.is_some_and(|p| p.iter().any(|p| p == "README.md"));
        if in_readme {
            let range = format!("{}..HEAD", f.commit);
            let mut args = vec!["log", "--format=%h %s", &range, "--"];
            args.extend(f.code.iter().map(String::as_str));
            let later = git(root, &args)?;
            if let Some(first) = later.lines().last() {
                problems.push(format!(
                    "README.md: {} predates a change to {}: {first} (`tools/figures refresh {}`)",
                    f.id,
                    f.code.join(" "),
                    f.id
                ));
            }
        }
    }
    Ok(problems)
}

/// The value at `path` in `v`: keys and list indices separated by dots.
fn at_path(v: &Value, path: &str) -> Option<f64> {
    let mut here = v;
    for key in path.trim().split('.') {
        here = match key.parse::<usize>() {
            Ok(i) if here.is_array() => here.get(i)?,
            _ => here.get(key)?,
        };
    }
    here.as_f64()
}

/// The figure `json` names in `v`: one path, or one divided by another.
#[must_use]
pub fn extract(v: &Value, json: &str) -> Option<f64> {
    match json.split_once(" / ") {
        Some((a, b)) => Some(at_path(v, a)? / at_path(v, b)?),
        None => at_path(v, json),
    }
}

/// This machine, as an entry records it.
#[must_use]
pub fn machine() -> Value {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, m)| m.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    json!({ "cores": cores, "cpu": cpu })
}

fn today() -> Result<String, String> {
    let out = Command::new("date")
        .arg("+%Y-%m-%d")
        .output()
        .map_err(|e| format!("date: {e}"))?;
    Ok(String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// Runs `command` from `root` through `sh -c`, its standard error passed through, and reads its
/// standard output as JSON.
fn run(root: &Path, command: &str) -> Result<Value, String> {
    eprintln!("figures: running `{command}`");
    let out = Command::new("sh")
        .args(["-c", command])
        .current_dir(root)
        .stderr(std::process::Stdio::inherit())
        .output()
        .map_err(|e| format!("sh: {e}"))?;
    if !out.status.success() {
        return Err(format!("`{command}` failed: {}", out.status));
    }
    serde_json::from_slice(&out.stdout).map_err(|e| format!("`{command}`: its output: {e}"))
}

/// Measures again the figures named in `ids` (every figure when empty) at the current commit:
/// each command run once, every entry and every marked number in the pages rewritten. Refuses a
/// working tree with changes to anything but the pages and the figures (an entry names the
/// commit it measured).
pub fn refresh(root: &Path, ids: &[String]) -> Result<Vec<String>, String> {
    let commit = clean_head(root)?;
    let mut outputs: BTreeMap<String, Value> = BTreeMap::new();
    let figures = load(root)?;
    for f in figures
        .iter()
        .filter(|f| ids.is_empty() || ids.contains(&f.id))
    {
        if !outputs.contains_key(&f.command) {
            outputs.insert(f.command.clone(), run(root, &f.command)?);
        }
    }
    let measured = Measured {
        commit,
        machine: machine(),
        date: today()?,
    };
    record(
        root,
        ids,
        &|command| outputs.get(command).cloned(),
        &measured,
    )
}

/// Records the figures named in `ids` from `output`, the JSON their command printed on another
/// machine (a lent one, with more cores or a GPU) at the current commit: `machine` is that
/// machine's `{ "cores": N, "cpu": "…" }`. Every id must share one command.
pub fn take(
    root: &Path,
    output: &Path,
    machine: Value,
    ids: &[String],
) -> Result<Vec<String>, String> {
    let commit = clean_head(root)?;
    let text = std::fs::read_to_string(output).map_err(|e| format!("{}: {e}", output.display()))?;
    let v: Value = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", output.display()))?;
    if machine["cores"].as_u64().is_none() || machine["cpu"].as_str().is_none() {
        return Err("the machine needs `cores` and `cpu`".into());
    }
    let figures = load(root)?;
    let commands: Vec<&str> = figures
        .iter()
        .filter(|f| ids.contains(&f.id))
        .map(|f| f.command.as_str())
        .collect();
    if ids.is_empty() || commands.iter().any(|c| *c != commands[0]) {
        return Err("name the figures of one command".into());
    }
    let measured = Measured {
        commit,
        machine,
        date: today()?,
    };
    record(root, ids, &|_| Some(v.clone()), &measured)
}

/// Where and when figures were measured.
struct Measured {
    commit: String,
    machine: Value,
    date: String,
}

/// HEAD, when the working tree has no change but to the pages and the figures.
fn clean_head(root: &Path) -> Result<String, String> {
    let dirty = git(root, &["status", "--porcelain", "--untracked-files=no"])?;
    // `XY PATH` a line; `git` trims the output, so the first line may have lost a blank X.
    let changed: Vec<&str> = dirty
        .lines()
        .filter_map(|l| l.trim_start().split_once(' ').map(|(_, p)| p.trim()))
        .filter(|p| !(p.ends_with(".md") || *p == FIGURES))
        .collect();
    if !changed.is_empty() {
        return Err(format!(
            "commit first: a figure names the commit it measured, and these are changed: {}",
            changed.join(" ")
        ));
    }
    git(root, &["rev-parse", "HEAD"])
}

/// Rewrites the entries named in `ids` (all when empty) from their command's output, and the
/// pages' marked numbers.
fn record(
    root: &Path,
    ids: &[String],
    output: &dyn Fn(&str) -> Option<Value>,
    measured: &Measured,
) -> Result<Vec<String>, String> {
    let mut figures = load(root)?;
    for id in ids {
        if !figures.iter().any(|f| &f.id == id) {
            return Err(format!("{id} is not in {FIGURES}"));
        }
    }
    let mut report = Vec::new();
    for f in figures
        .iter_mut()
        .filter(|f| ids.is_empty() || ids.contains(&f.id))
    {
        let v = output(&f.command).ok_or_else(|| format!("{}: no output", f.id))?;
        let raw = extract(&v, &f.json)
            .ok_or_else(|| format!("{}: `{}` is not a number in the output", f.id, f.json))?;
        let old = f.printed();
        let factor = 10f64.powi(f.digits as i32);
        f.value = (raw * f.scale * factor).round() / factor;
        f.commit = measured.commit.clone();
        f.machine = measured.machine.clone();
        f.date = measured.date.clone();
        report.push(format!("{}: {old} -> {} {}", f.id, f.printed(), f.unit));
    }
    save(root, &figures)?;
    rewrite_pages(root, &figures)?;
    Ok(report)
}

/// Writes each marked number of the pages as its entry prints it (thousands separators kept
/// where the page had them).
fn rewrite_pages(root: &Path, figures: &[Figure]) -> Result<(), String> {
    let by_id: BTreeMap<&str, &Figure> = figures.iter().map(|f| (f.id.as_str(), f)).collect();
    for page in pages(root) {
        let text =
            std::fs::read_to_string(&page).map_err(|e| format!("{}: {e}", page.display()))?;
        let mut out = text.clone();
        for m in marks(&text).iter().rev() {
            if let Some(f) = by_id.get(m.id.as_str()) {
                let mut new = f.printed();
                if m.written.contains(',') {
                    new = with_separators(&new);
                }
                out.replace_range(m.range.clone(), &new);
            }
        }
        if out != text {
            write_whole(&page, &out)?;
        }
    }
    Ok(())
}

/// `1234567.5` as `1,234,567.5`.
#[must_use]
pub fn with_separators(number: &str) -> String {
    let (sign, digits) = match number.strip_prefix('-') {
        Some(d) => ("-", d),
        None => ("", number),
    };
    let (whole, fraction) = digits
        .split_once('.')
        .map_or((digits, None), |(w, f)| (w, Some(f)));
    let mut grouped = String::new();
    for (i, c) in whole.chars().enumerate() {
        if i > 0 && (whole.len() - i) % 3 == 0 {
            grouped.push(',');
        }
        grouped.push(c);
    }
    match fraction {
        Some(f) => format!("{sign}{grouped}.{f}"),
        None => format!("{sign}{grouped}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mark_takes_the_number_right_before_it() {
        let page = "build 0.141<!--fig:core.build--> s\n6.6<!--fig:x-->× and −1,234.5<!--fig:y-->";
        let m = marks(page);
        assert_eq!(m.len(), 3);
        assert_eq!(
            (m[0].id.as_str(), m[0].written.as_str()),
            ("core.build", "0.141")
        );
        assert_eq!((m[1].written.as_str(), m[1].line), ("6.6", 2));
        assert_eq!(plain(&m[2].written), "-1234.5");
        assert_eq!(marks("no number <!--fig:z-->")[0].written, "");
    }

    #[test]
    fn paths_and_ratios_are_read_from_the_json() {
        let v = json!({ "a": [{ "t": 3.0 }, { "t": 12.0 }], "b": { "t": 4.0 } });
        assert_eq!(extract(&v, "a.1.t"), Some(12.0));
        assert_eq!(extract(&v, "a.1.t / b.t"), Some(3.0));
        assert_eq!(extract(&v, "a.2.t"), None);
        assert_eq!(extract(&v, "b"), None);
    }

    #[test]
    fn separators_group_the_whole_part() {
        assert_eq!(with_separators("1044943"), "1,044,943");
        assert_eq!(with_separators("-2543704.25"), "-2,543,704.25");
        assert_eq!(with_separators("912"), "912");
    }
}

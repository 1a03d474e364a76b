//! What an ensemble returns: its accessors, its CSV and its printed table.

use super::*;

impl<R> Results<R> {
    /// How many members failed.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// // A NaN end time is rejected before any step: every member fails, in its own slot.
    /// let r = Ensemble::new(3, |_| Member::new(Free, [0.0], [1.0])).configure(|sim| sim.until(f64::NAN)).run();
    /// assert_eq!(r.failures(), 3);
    /// ```
    pub fn failures(&self) -> usize {
        self.results.iter().filter(|r| r.is_err()).count()
    }
}

impl Results<Vec<f64>> {
    /// Writes one row per member: `member`, the parameters by name, the reduction's columns, and
    /// `error` (empty, or the member's error as a sentence, its values then empty). With `header
    /// = false` the header line is left out (for the second and later shards of a job array).
    ///
    /// There is one parameter column per distinct name, in the order the names are first met
    /// (member order, then each member's order); a member without a name has an empty cell there.
    /// A shard's columns are those of its own members, so shards concatenate when every member
    /// has the same names. Fields holding a comma, a quote or a line break are quoted as RFC 4180
    /// says (inner quotes doubled). Missing parent folders are created.
    ///
    /// # Errors
    ///
    /// [`std::io::ErrorKind::InvalidInput`], before anything is written, when a member's row has
    /// not one value per column (the reduction returned more or fewer values than `columns`
    /// names) or a member names a parameter twice; otherwise the I/O error, naming the path.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let r = Ensemble::new(2, |i| Member::new(Free, [0.0], [i as f64]).param("v", i as f64))
    ///     .configure(|sim| sim.until(1.0))
    ///     .reduce(&["x"], |tr| vec![tr.q[tr.q.len() - 1][0]]);
    /// let path = std::env::temp_dir().join(format!("lagrange-doc-{}.csv", std::process::id()));
    /// r.write_csv(&path, true).unwrap();
    /// let text = std::fs::read_to_string(&path).unwrap();
    /// assert_eq!(text.lines().next(), Some("member,v,x,error"));
    /// std::fs::remove_file(&path).unwrap();
    /// ```
    pub fn write_csv(&self, path: impl AsRef<Path>, header: bool) -> std::io::Result<()> {
        let path = path.as_ref();
        let text = self.csv_text(header)?;
        let named = |e: std::io::Error| {
            std::io::Error::new(e.kind(), format!("writing {}: {e}", path.display()))
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(named)?;
        }
        let mut w = std::io::BufWriter::new(std::fs::File::create(path).map_err(named)?);
        w.write_all(text.as_bytes()).map_err(named)?;
        w.flush().map_err(named)
    }

    /// The CSV of [`Results::write_csv`] as text, checked before any of it is written.
    fn csv_text(&self, header: bool) -> std::io::Result<String> {
        let mut out = String::new();
        for (r, row) in self.cells(header)?.iter().enumerate() {
            let last = row.len() - 1;
            let cells: Vec<String> = row
                .iter()
                .enumerate()
                .map(|(k, c)| {
                    // A data row's error is always quoted (a sentence); every other field as RFC
                    // 4180 needs.
                    if k == last && !c.is_empty() && (r > 0 || !header) {
                        format!("\"{}\"", c.replace('"', "\"\""))
                    } else {
                        csv_field(c)
                    }
                })
                .collect();
            out.push_str(&cells.join(","));
            out.push('\n');
        }
        Ok(out)
    }

    /// The table of [`Results::write_csv`], unquoted: the header (with `header`), then a row per
    /// member; checked (a parameter named twice, a reduction of the wrong length) first.
    fn cells(&self, header: bool) -> std::io::Result<Vec<Vec<String>>> {
        let invalid = |msg: String| std::io::Error::new(std::io::ErrorKind::InvalidInput, msg);
        // One column per distinct parameter name, in first-seen order.
        let mut names: Vec<&str> = Vec::new();
        for (p, i) in self.params.iter().zip(&self.index) {
            for (k, (n, _)) in p.iter().enumerate() {
                if p[..k].iter().any(|(m, _)| m == n) {
                    return Err(invalid(format!(
                        "member {i} names the parameter {n:?} twice: give each parameter of a \
                         member its own name (one CSV column per name)"
                    )));
                }
                if !names.contains(n) {
                    names.push(n);
                }
            }
        }
        for (i, r) in self.index.iter().zip(&self.results) {
            if let Ok(vals) = r
                && vals.len() != self.columns.len()
            {
                return Err(invalid(format!(
                    "member {i}: the reduction returned {} values for {} columns ({}); \
                         return one value per column named in `reduce` (no CSV written)",
                    vals.len(),
                    self.columns.len(),
                    self.columns.join(", ")
                )));
            }
        }
        let mut rows = Vec::new();
        if header {
            let mut cols = vec!["member".to_string()];
            cols.extend(names.iter().map(|n| n.to_string()));
            cols.extend(self.columns.iter().cloned());
            cols.push("error".to_string());
            rows.push(cols);
        }
        for ((i, p), r) in self.index.iter().zip(&self.params).zip(&self.results) {
            let mut row = vec![i.to_string()];
            row.extend(names.iter().map(|n| {
                p.iter()
                    .find(|(m, _)| m == n)
                    .map_or(String::new(), |(_, v)| csv_number(*v))
            }));
            match r {
                Ok(vals) => {
                    row.extend(vals.iter().map(|&v| csv_number(v)));
                    row.push(String::new());
                }
                Err(e) => {
                    row.extend(self.columns.iter().map(|_| String::new()));
                    // One line per member: a line break in the message becomes a space.
                    row.push(e.to_string().replace(['\r', '\n'], " "));
                }
            }
            rows.push(row);
        }
        Ok(rows)
    }
}

/// A number as a CSV cell that spreadsheets read and that reads back to the same f64: an
/// integer as an integer (19, not 1.9e1), other values in plain decimals where that is short
/// (2.006066806131417, 0.0005), in exponent form only outside 1e-5 … 1e16 (1e-20).
pub(super) fn csv_number(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-5..1e16).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

impl core::fmt::Display for Results<Vec<f64>> {
    /// The table of [`Results::write_csv`] in aligned columns, for a terminal (a row per member;
    /// the reason in place of the values of a member that failed).
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let r = Ensemble::new(2, |i| Member::new(Free, [0.0], [i as f64]).param("v", i as f64))
    ///     .configure(|s| s.until(1.0))
    ///     .reduce(&["v0"], |tr| vec![tr.qdot[0][0]]);
    /// assert_eq!(r.to_string(), "member  v  v0  error\n0       0  0   \n1       1  1   \n");
    /// ```
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let rows = self.cells(true).map_err(|_| core::fmt::Error)?;
        let mut width = vec![0usize; rows.first().map_or(0, Vec::len)];
        for row in &rows {
            for (w, c) in width.iter_mut().zip(row) {
                *w = (*w).max(c.chars().count());
            }
        }
        for row in &rows {
            for (k, c) in row.iter().enumerate() {
                if k + 1 == row.len() {
                    f.write_str(c)?;
                } else {
                    write!(f, "{c:<w$}  ", w = width[k])?;
                }
            }
            f.write_str("\n")?;
        }
        Ok(())
    }
}

/// A CSV field as RFC 4180 says: quoted, its quotes doubled, when it holds a comma, a quote or a
/// line break; as it is otherwise.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

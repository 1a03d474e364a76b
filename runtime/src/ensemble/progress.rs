//! The progress bar of a long ensemble (feature `progress`).

/// The progress bar's line: members done of all, the bar, the time elapsed and the estimated time
/// left (`[00:00:12] ████████░░░░  512/1024 members, 00:00:12 left`).
#[cfg(feature = "progress")]
pub(super) const PROGRESS_TEMPLATE: &str =
    "[{elapsed_precise}] {wide_bar} {pos}/{len} members, {eta_precise} left";

/// The progress bar (a no-op without the `progress` feature or when not asked for).
pub(super) struct Bar {
    #[cfg(feature = "progress")]
    bar: Option<indicatif::ProgressBar>,
}

impl Bar {
    pub(super) fn new(show: bool, len: usize) -> Self {
        #[cfg(feature = "progress")]
        {
            Bar {
                bar: show.then(|| {
                    indicatif::ProgressBar::new(len as u64).with_style(
                        indicatif::ProgressStyle::with_template(PROGRESS_TEMPLATE)
                            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
                    )
                }),
            }
        }
        #[cfg(not(feature = "progress"))]
        {
            let _ = (show, len);
            Bar {}
        }
    }
    pub(super) fn inc(&self) {
        #[cfg(feature = "progress")]
        if let Some(b) = &self.bar {
            b.inc(1);
        }
    }
    pub(super) fn finish(&self) {
        #[cfg(feature = "progress")]
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

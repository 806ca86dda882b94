//! Counts of the importer's work on each thread, so that tests can check that an import
//! costs time linear in its input and that its size limit comes before any element is
//! converted, by counting rather than timing.

use std::cell::Cell;

/// What the importer has done on the calling thread since the thread started. An import
/// runs on the thread that calls it: the difference of two snapshots taken before and
/// after ([`Work::since`]) is that import's work.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Work {
    /// Lines of text scanned for table headers (each element's line in messages).
    pub lines_scanned: u64,
    /// `ShaftElement` tables converted into elements.
    pub shaft_elements_converted: u64,
    /// Names tried for the materials: one per distinct material, and one more per
    /// `-2`, `-3`, … suffix tried for a name that ROSS gave different values.
    pub material_names_tried: u64,
}

thread_local! {
    static WORK: Cell<Work> = const {
        Cell::new(Work { lines_scanned: 0, shaft_elements_converted: 0, material_names_tried: 0 })
    };
}

impl Work {
    /// The calling thread's counts so far.
    pub fn this_thread() -> Work {
        WORK.with(Cell::get)
    }

    /// The work done since `earlier`, a snapshot of the same thread.
    pub fn since(&self, earlier: &Work) -> Work {
        Work {
            lines_scanned: self.lines_scanned.saturating_sub(earlier.lines_scanned),
            shaft_elements_converted: self.shaft_elements_converted.saturating_sub(earlier.shaft_elements_converted),
            material_names_tried: self.material_names_tried.saturating_sub(earlier.material_names_tried),
        }
    }
}

/// Add to the calling thread's counts.
pub(crate) fn add(f: impl FnOnce(&mut Work)) {
    WORK.with(|w| {
        let mut work = w.get();
        f(&mut work);
        w.set(work);
    });
}

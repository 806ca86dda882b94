//! The one place that writes, locks or deletes on disk, and trusts nothing it finds there.
//!
//! - Files are opened with `O_NOFOLLOW` and checked on the open handle: a symbolic link,
//!   a FIFO, a device or a socket where the tool reads a record or writes a file is
//!   refused ([`Refused`]), never followed, never replaced.
//! - New files are created exclusively (`O_CREAT | O_EXCL`): an existing file, or a link
//!   planted in the meantime, is never opened for writing.
//! - A name read from a record (a manifest) is used only when it is a plain name, one
//!   path component that stays inside the folder ([`plain_name`]).
//! - What the tool removes it proves it wrote: by content ([`remove_file_if`]) or by a
//!   run-unique [`token`] recorded inside the folder it removes.
//! - Every write, rename and removal passes a fault point ([`fault`]), where a test can
//!   kill the process to check that every interruption leaves a consistent folder.
//!
//! Everything here returns `std::io::Result`; a refusal is an `io::Error` carrying a
//! [`Refused`], which the crate's error turns into `Error::Unsafe` (exit code 2).

mod atomic;
pub mod fault;
mod names;
mod open;
mod swap;

pub use atomic::{remove_temporaries, temporary_target, write_atomic, TEMPORARY_PREFIX};
pub use names::{host, old_staging, plain_name, staging_name, staging_parts, token, HIDDEN_PREFIX};
pub use open::{
    create_dir, create_new, ensure_dir, open_existing, open_lock, read, read_to_string, real_dir, remove_file_if,
    replaceable, standing, Refused, Standing,
};
pub use swap::{copy_link, exchange, hard_link, remove_dir_all, rename, rename_new};

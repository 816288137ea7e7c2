//! Saving and restoring damage: a context records the damage of the bodies it is told to, as
//! dentbend's damage file (JSON: each dent as a compact edit of the mesh); a body restored from
//! it gets its saved mesh bit for bit, with no simulation.

use std::ffi::{CStr, c_char, c_int};

use dentbend::damage::DentedTarget;
use dentbend::dent::changed_vertices;
use dentbend::record::{DamageFile, DentForm, Projectiles, replay_body, replay_body_asset};

use crate::damage::DbDamage;
use crate::status::{Failure, guarded, guarded_value, hand_out};

/// Reads a NUL-terminated UTF-8 name.
///
/// # Safety
/// `name` is null or a NUL-terminated string.
unsafe fn name<'a>(name: *const c_char) -> Result<&'a str, Failure> {
    if name.is_null() {
        return Err(Failure::null("name"));
    }
    // SAFETY: not null, NUL-terminated by the caller's contract.
    unsafe { CStr::from_ptr(name) }.to_str().map_err(|_| Failure::invalid("name is not UTF-8"))
}

/// Records body `id`'s damage from now on, as the body `name` of the saved file: its mesh now is
/// the base a restore starts from.
///
/// # Safety
/// `damage` is null or live; `body_name` is null or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_record(damage: *mut DbDamage, id: u64, body_name: *const c_char) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let (damage, body_name) = unsafe { (DbDamage::get_mut(damage)?, name(body_name)?) };
        damage.record(id, body_name)
    })
}

/// The recorded bodies' damage as a damage file (JSON, its length written to `length`); null
/// and 0 on failure. Valid until the next save or step.
///
/// # Safety
/// `damage` is null or live; `length` is null or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_save(damage: *mut DbDamage, length: *mut usize) -> *const u8 {
    let saved = guarded_value(|| {
        // SAFETY: the caller's contract.
        let damage = unsafe { DbDamage::get_mut(damage)? };
        damage.save().map(|saved| (saved.as_ptr(), saved.len()))
    });
    // SAFETY: the caller's contract.
    unsafe { hand_out(saved, length) }
}

/// Gives body `id` the damage the file's body `name` recorded (saved from a body with the mesh
/// this one has now): its mesh becomes the saved one (its UVs and normals brought along), and
/// a recorded body's record goes on from it. A file for another mesh, or one that does not replay, is refused and changes
/// nothing.
///
/// # Safety
/// `damage` is null or live; `file` holds `length` bytes; `body_name` is null or a
/// NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_restore(
    damage: *mut DbDamage,
    id: u64,
    file: *const u8,
    length: usize,
    body_name: *const c_char,
) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let (damage, body_name) = unsafe { (DbDamage::get_mut(damage)?, name(body_name)?) };
        if file.is_null() {
            return Err(Failure::null("file"));
        }
        if length as u64 > DamageFile::MAX_FILE_BYTES {
            return Err(Failure::invalid(format!(
                "{length} bytes: a damage file is at most {}",
                DamageFile::MAX_FILE_BYTES
            )));
        }
        // SAFETY: not null, `length` bytes by the caller's contract.
        let bytes = unsafe { std::slice::from_raw_parts(file, length) };
        damage.restore(id, bytes, body_name)
    })
}

impl DbDamage {
    /// Records body `id`'s damage from now on, as the body `body_name` of the saved file: its
    /// mesh now is the base a restore starts from.
    ///
    /// # Errors
    /// A body that does not dent.
    pub fn record(&mut self, id: u64, body_name: &str) -> Result<(), Failure> {
        let mesh = self.targets.mesh(id).ok_or_else(|| Failure::invalid(format!("body {id} does not dent")))?;
        self.recorder.track(id, body_name, mesh);
        Ok(())
    }

    /// The recorded bodies' damage as a damage file (JSON), kept until the next save.
    ///
    /// # Errors
    /// A file that cannot be written (it never is for recorded damage).
    pub fn save(&mut self) -> Result<&[u8], Failure> {
        self.saved = self.recorder.file().to_json().map_err(|e| Failure::invalid(e.to_string()))?;
        Ok(&self.saved)
    }

    /// Gives body `id` the damage the damage file `bytes`' body `body_name` recorded (saved
    /// from a body with the mesh this one has now): its mesh becomes the saved one, and a
    /// recorded body's record goes on from it.
    ///
    /// # Errors
    /// A file that does not parse, has no such body, is for another mesh or does not replay; a
    /// body on the replication stream. Nothing changes then.
    pub fn restore(&mut self, id: u64, bytes: &[u8], body_name: &str) -> Result<(), Failure> {
        if bytes.len() as u64 > DamageFile::MAX_FILE_BYTES {
            return Err(Failure::invalid(format!(
                "{} bytes: a damage file is at most {}",
                bytes.len(),
                DamageFile::MAX_FILE_BYTES
            )));
        }
        let file = DamageFile::from_json(bytes).map_err(|e| Failure::invalid(e.to_string()))?;
        let body =
            file.body(body_name).ok_or_else(|| Failure::invalid(format!("the file has no body {body_name:?}")))?;
        let now = self.targets.mesh(id).ok_or_else(|| Failure::invalid(format!("body {id} does not dent")))?;
        if self.stream.carries(id) {
            return Err(Failure::invalid(format!(
                "body {id} is on the replication stream: restore it before db_damage_replicate (clients would \
                 dent the mesh they have)"
            )));
        }
        // A body with attributes brings them through each record as it replays.
        let (restored, asset) = match self.attributes.get(id) {
            None => {
                let replayed = replay_body(body, now, DentForm::Edits, &Projectiles::new());
                (replayed.map_err(|e| Failure::invalid(e.to_string()))?.mesh, None)
            }
            Some(asset) => {
                let replayed = replay_body_asset(body, asset, (DentForm::Edits, &Projectiles::new()));
                let (replayed, asset) = replayed.map_err(|e| {
                    Failure::invalid(format!(
                        "{e}: the body's UVs and normals cannot follow this damage file (saved without its \
                         refinements); add the body without them to restore it"
                    ))
                })?;
                (replayed.mesh, Some(asset))
            }
        };
        let moved = changed_vertices(now, &restored);
        let topology_changed = now.faces() != restored.faces();
        if self.recorder.body(id).is_some() {
            self.recorder.resume(id, body.clone());
        }
        self.damage.forget(id);
        let dented = DentedTarget { key: id, mesh: restored, moved, refinement: Default::default(), topology_changed };
        self.moved.extend(self.targets.apply(vec![dented]));
        if let Some(asset) = asset {
            self.attributes.replace(id, asset);
        }
        Ok(())
    }
}

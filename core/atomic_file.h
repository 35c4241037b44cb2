#pragma once
// Writing outputs so that a failed or interrupted run never leaves a partial file or a partial
// set of files, and never replaces anything but a regular file.
//
//   * Every output is written to a temporary "<stem>.tmp-<pid>-<n><ext>" beside its target with
//     checked system calls (every write, the final fdatasync and close; ENOSPC or EIO anywhere is
//     an InputError naming the target, exit 1), then renamed over the target.
//   * Only a regular file (or nothing) may sit at the target. A symlink, directory, device, FIFO
//     or socket there is an InputError; it is never replaced (`--stats /dev/null` must not turn
//     the device into a regular file when run as root).
//   * Output sets. While an OutputSet is alive (each `littoral` command opens one), commit() only
//     stages the finished temporary; OutputSet::commit() renames all of them at the end. If the
//     set is destroyed without commit (an error unwound), its temporaries, any files it had
//     already renamed and the folders it created are removed: the set is complete or absent.
//   * SIGINT and SIGTERM (installInterruptCleanup) remove the same things and exit 130 / 143.
//
// Without a current OutputSet (library use, unit tests) commit() renames at once.
#include <filesystem>
#include <string>
#include <string_view>

namespace littoral {

// InputError (naming `target`) if something other than a regular file exists at `target`
// (checked with lstat, so a symlink is refused even if it points at a regular file), or if the
// file there is one this process has read as an input (noteInput): no command writes over one of
// its own inputs (scene files, meshes, rasters, textures, class maps, spectra, IRs).
void checkOutputTarget(const std::filesystem::path& target);

// An output this run does not write (an optional one: a true-colour preview, a detector image,
// K_d profiles, georeferencing layers) left in the output folder by an earlier run would sit beside
// outputs it does not belong to: removed if present, with a note naming it and `what` it is.
// Returns whether a file was removed.
bool removeStaleOutput(const std::filesystem::path& target, std::string_view what);

// Records `path` (if it is a regular file) as an input of this process, by device and inode, so
// that checkOutputTarget refuses to replace it under any name. requireRegularInputFile (and so
// readTextFile) calls it; readers that open files another way call it themselves.
void noteInput(const std::filesystem::path& path);
// Forgets `path` as an input: for a command's own state that it reads and then replaces (the
// checkpoint of a resumed progressive render).
void forgetInput(const std::filesystem::path& path);
// Forgets every noted input (for tests that run several commands in one process).
void clearNotedInputs();

// Creates `dir` and its missing parents. Folders created while an OutputSet is current are
// removed again if the set rolls back. InputError naming `dir` (prefixed with `option`, e.g.
// "--out", when given) if a path component exists and is not a folder, or a folder cannot be
// created or written (read-only file system, permissions).
void createOutputFolder(const std::filesystem::path& dir, std::string_view option = "");

// The same checks without creating anything: every existing component of `dir` is a folder and
// the deepest existing one is writable. For checking outputs before a long computation.
void checkOutputFolder(const std::filesystem::path& dir, std::string_view option = "");

class AtomicOutput {
public:
    // Checks the target (checkOutputTarget), creates its folder (createOutputFolder) and reserves
    // an empty temporary beside it (O_EXCL). InputError on any failure.
    explicit AtomicOutput(std::filesystem::path target);
    ~AtomicOutput();  // removes the temporary unless committed
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;

    const std::filesystem::path& tempPath() const { return temp_; }
    const std::filesystem::path& target() const { return target_; }
    // Replaces the temporary's content with `bytes` using checked write(2), fdatasync(2) and
    // close(2); InputError naming the target with the system's reason (e.g. "No space left on
    // device") if any of them fails.
    void write(std::string_view bytes);
    // Publishes the temporary: renames it over the target, or stages it in the current
    // OutputSet. Checks the target again first.
    void commit();

private:
    std::filesystem::path target_, temp_;
    bool committed_ = false;
};

// Convenience: write `bytes` to `target` atomically.
void writeFileAtomic(const std::filesystem::path& target, std::string_view bytes);
inline void writeTextFileAtomic(const std::filesystem::path& target, const std::string& text) {
    writeFileAtomic(target, text);
}

// A command's claim on its output folder, for the command's lifetime: the file DIR/.littoral.lock
// holds the owner's process id (created with O_EXCL). A second command into the same folder is
// refused (InputError naming the folder and the owner) while the owner runs; a lock left by a
// process that no longer runs (killed with SIGKILL, a crash) is taken over with a warning. The lock
// is removed when the command ends, however it ends (also on SIGINT/SIGTERM). Creates the folder
// (createOutputFolder) if it does not exist. In an MPI run, rank 0 takes the lock for every rank (the
// others only check the folder).
class OutputFolderLock {
public:
    explicit OutputFolderLock(const std::filesystem::path& dir, std::string_view option = "--out");
    ~OutputFolderLock();
    OutputFolderLock(const OutputFolderLock&) = delete;
    OutputFolderLock& operator=(const OutputFolderLock&) = delete;
    static constexpr const char* kFileName = ".littoral.lock";

private:
    std::string path_;
};

// The outputs of one command: complete or absent (see the top of this file). Sets do not nest.
class OutputSet {
public:
    OutputSet();
    ~OutputSet();  // rolls back unless commit() succeeded
    OutputSet(const OutputSet&) = delete;
    OutputSet& operator=(const OutputSet&) = delete;
    // Renames every staged temporary over its target, in the order they were staged. If one
    // fails, the exception propagates and the destructor rolls back (including the files this
    // commit already renamed).
    void commit();
    static bool active();
};

// While alive, files are written as if no set were current (each renamed over its target at
// once, folders not removed on a rollback): for scratch files outside every output folder that
// a command removes itself (check-scene's temporary copy of the textures it builds). The set's
// staged files are untouched and it resumes when the pause ends. Not for concurrent use.
class OutputSetPause {
public:
    OutputSetPause();
    ~OutputSetPause();
    OutputSetPause(const OutputSetPause&) = delete;
    OutputSetPause& operator=(const OutputSetPause&) = delete;

private:
    bool wasActive_ = false;
};

// Publishes what the current set has staged so far and makes it permanent (a later rollback
// keeps it). For outputs that must survive a later failure of the same command: the
// validity.json of a rejected build, the synthetic site that `demo` then builds from.
// Without a current set this does nothing.
void publishStagedOutputs();

// Renames what the current set has staged so far over its targets, so that the command can read
// those files back (a scene file it then builds), but keeps them in the set: a later rollback or
// interrupt still removes them and the folders the set created. For commands whose later steps read
// their own earlier outputs (the image-quality study's run folders). Without a current set this
// does nothing.
void exposeStagedOutputs();

// Blocks SIGINT and SIGTERM in the calling thread (threads created later inherit the mask; call
// it first in main) and starts a thread that waits for them. On either signal it removes this
// run's temporaries, the files of a set being published and the folders the set created, prints
// one line on stderr and exits with status 128 + signal (130 for SIGINT, 143 for SIGTERM).
void installInterruptCleanup();

// Reads a whole regular file; InputError naming the path if it does not exist, is a folder or a
// special file (a device, FIFO or socket, which could block or never end), is larger than the
// memory budget, or cannot be read.
std::string readTextFile(const std::filesystem::path& path);

// InputError naming `path` (prefixed by `what`, e.g. "scene file") unless it is an existing
// regular file (symlinks to one are fine). Says which of missing / folder / special it is.
void requireRegularInputFile(const std::filesystem::path& path, std::string_view what = "file");

}  // namespace littoral

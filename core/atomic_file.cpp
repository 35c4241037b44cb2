#include "core/atomic_file.h"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"
#include "core/ranks.h"
#include "core/resource_limits.h"

namespace littoral {

namespace fs = std::filesystem;

namespace {

std::string sysError(int err) { return std::strerror(err); }

// What lstat says sits at a path, for messages.
const char* kindOf(mode_t m) {
    if (S_ISLNK(m)) return "a symbolic link";
    if (S_ISDIR(m)) return "a folder";
    if (S_ISCHR(m)) return "a character device";
    if (S_ISBLK(m)) return "a block device";
    if (S_ISFIFO(m)) return "a FIFO (named pipe)";
    if (S_ISSOCK(m)) return "a socket";
    return "a special file";
}

// Everything this process would have to remove if it stopped now. One mutex guards it; the
// interrupt thread takes the mutex and never releases it (it exits the process), so no file is
// created or renamed after the cleanup has looked at the lists.
struct Registry {
    std::mutex m;
    std::vector<std::string> temps;        // temporaries that exist (or are about to)
    struct Staged { std::string temp, target; };
    std::vector<Staged> staged;            // finished temporaries waiting for OutputSet::commit
    std::vector<std::string> published;    // targets renamed by the set being committed
    std::vector<std::string> createdDirs;  // folders the current set created, in creation order
    std::vector<std::string> locks;        // output-folder locks held (removed on an interrupt too)
    bool setActive = false;
};

Registry& registry() {
    static Registry* r = new Registry;  // never destroyed: the interrupt thread may use it at exit
    return *r;
}

void eraseValue(std::vector<std::string>& v, const std::string& s) {
    auto it = std::find(v.begin(), v.end(), s);
    if (it != v.end()) v.erase(it);
}

// Removes staged temporaries, published targets and created folders. Caller holds the mutex.
void rollbackLocked(Registry& r) {
    for (const auto& l : r.locks) ::unlink(l.c_str());  // first: a lock would keep its folder from being removed
    for (const auto& s : r.staged) ::unlink(s.temp.c_str());
    for (const auto& t : r.temps) ::unlink(t.c_str());
    for (const auto& p : r.published) ::unlink(p.c_str());
    for (auto it = r.createdDirs.rbegin(); it != r.createdDirs.rend(); ++it) ::rmdir(it->c_str());  // only if empty
    r.staged.clear();
    r.temps.clear();
    r.published.clear();
    r.createdDirs.clear();
}

std::atomic<unsigned> gTempCounter{0};

}  // namespace

namespace {
// The files this process has read (device and inode, with the path they were read as): no output
// may replace one of them.
struct InputFiles {
    std::mutex m;
    std::map<std::pair<dev_t, ino_t>, std::string> files;
};
InputFiles& inputFiles() {
    static InputFiles f;
    return f;
}

void noteInputStat(const struct stat& st, const fs::path& path) {
    InputFiles& f = inputFiles();
    std::lock_guard<std::mutex> lock(f.m);
    f.files.emplace(std::pair{st.st_dev, st.st_ino}, path.string());
}
}  // namespace

void noteInput(const fs::path& path) {
    struct stat st;
    if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) noteInputStat(st, path);
}

void forgetInput(const fs::path& path) {
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) return;
    InputFiles& f = inputFiles();
    std::lock_guard<std::mutex> lock(f.m);
    f.files.erase({st.st_dev, st.st_ino});
}

void clearNotedInputs() {
    InputFiles& f = inputFiles();
    std::lock_guard<std::mutex> lock(f.m);
    f.files.clear();
}

void checkOutputTarget(const fs::path& target) {
    struct stat st;
    if (::lstat(target.c_str(), &st) != 0) {
        if (errno == ENOENT) return;
        if (errno == ENOTDIR)
            throw InputError(SourceLoc{target.string()}, "cannot write output: a component of the path is a file, not a folder");
        throw InputError(SourceLoc{target.string()}, "cannot write output: " + sysError(errno));
    }
    if (!S_ISREG(st.st_mode))
        throw InputError(SourceLoc{target.string()},
                         fmt::format("refusing to write output: {} is in the way; Littoral replaces only regular "
                                     "files (remove it or choose another name)",
                                     kindOf(st.st_mode)));
    InputFiles& f = inputFiles();
    std::lock_guard<std::mutex> lock(f.m);
    const auto it = f.files.find({st.st_dev, st.st_ino});
    // A noted input that is no longer at its path with that inode was deleted (a scratch file the
    // command removed), and the file system has since given its inode to this target.
    struct stat now;
    if (it != f.files.end() &&
        (::stat(it->second.c_str(), &now) != 0 || now.st_dev != st.st_dev || now.st_ino != st.st_ino)) {
        f.files.erase(it);
        return;
    }
    if (it != f.files.end())
        throw InputError(SourceLoc{target.string()},
                         fmt::format("refusing to write output: it would replace '{}', which this command reads as an "
                                     "input; write the outputs to another folder (--out)",
                                     it->second));
}

bool removeStaleOutput(const fs::path& target, std::string_view what) {
    std::error_code ec;
    if (!fs::remove(target, ec)) return false;
    log::info("removed {}, {} of an earlier run that this one does not write", target.string(), what);
    return true;
}

void createOutputFolder(const fs::path& dirIn, std::string_view option) {
    const fs::path dir = dirIn.empty() ? fs::path(".") : dirIn;
    const std::string prefix = option.empty() ? std::string() : std::string(option) + ": ";
    auto fail = [&](const fs::path& where, const std::string& why) -> InputError {
        return InputError(SourceLoc{where.string()}, prefix + why);
    };
    // Walk from the root down, creating what is missing.
    fs::path cur;
    for (const auto& part : dir) {
        cur /= part;
        if (part == "/" || part.empty()) continue;
        struct stat st;
        if (::stat(cur.c_str(), &st) == 0) {
            if (!S_ISDIR(st.st_mode))
                throw fail(cur, fmt::format("cannot create output folder '{}': '{}' exists and is not a folder",
                                            dir.string(), cur.string()));
            continue;
        }
        if (errno != ENOENT) throw fail(cur, fmt::format("cannot create output folder '{}': {}", dir.string(), sysError(errno)));
        Registry& r = registry();
        std::lock_guard<std::mutex> lock(r.m);
        if (::mkdir(cur.c_str(), 0777) != 0 && errno != EEXIST)
            throw fail(cur, fmt::format("cannot create output folder '{}': {}", dir.string(), sysError(errno)));
        if (r.setActive) r.createdDirs.push_back(cur.string());
    }
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
        throw fail(dir, fmt::format("output folder '{}' is not writable: {}", dir.string(), sysError(errno)));
}

void checkOutputFolder(const fs::path& dirIn, std::string_view option) {
    const fs::path dir = dirIn.empty() ? fs::path(".") : dirIn;
    const std::string prefix = option.empty() ? std::string() : std::string(option) + ": ";
    fs::path cur, deepest = dir.is_absolute() ? fs::path("/") : fs::path(".");
    for (const auto& part : dir) {
        cur /= part;
        if (part == "/" || part.empty()) continue;
        struct stat st;
        if (::stat(cur.c_str(), &st) != 0) {
            if (errno == ENOENT) break;  // created when the outputs are written
            throw InputError(SourceLoc{cur.string()}, fmt::format("{}cannot use output folder '{}': {}", prefix,
                                                                  dir.string(), sysError(errno)));
        }
        if (!S_ISDIR(st.st_mode))
            throw InputError(SourceLoc{cur.string()}, fmt::format("{}cannot create output folder '{}': '{}' exists and "
                                                                  "is not a folder",
                                                                  prefix, dir.string(), cur.string()));
        deepest = cur;
    }
    if (::access(deepest.c_str(), W_OK | X_OK) != 0)
        throw InputError(SourceLoc{deepest.string()}, fmt::format("{}output folder '{}' cannot be written: {}", prefix,
                                                                  deepest.string(), sysError(errno)));
}

AtomicOutput::AtomicOutput(fs::path target) : target_(std::move(target)) {
    checkOutputTarget(target_);
    if (target_.has_parent_path()) createOutputFolder(target_.parent_path());
    // Keep the extension last so that libraries choosing a format by extension still work.
    Registry& r = registry();
    for (int attempt = 0;; ++attempt) {
        temp_ = target_.parent_path() / fmt::format("{}.tmp-{}-{}{}", target_.stem().string(), ::getpid(),
                                                    gTempCounter.fetch_add(1), target_.extension().string());
        std::lock_guard<std::mutex> lock(r.m);
        const int fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) {
            ::close(fd);
            r.temps.push_back(temp_.string());
            return;
        }
        if (errno != EEXIST || attempt > 100)
            throw InputError(SourceLoc{target_.string()}, "cannot create output: " + sysError(errno));
    }
}

AtomicOutput::~AtomicOutput() {
    if (committed_) return;
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.m);
    ::unlink(temp_.c_str());
    eraseValue(r.temps, temp_.string());
}

void AtomicOutput::write(std::string_view bytes) {
    const std::string where = target_.string();
    const int fd = ::open(temp_.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0) throw InputError(SourceLoc{where}, "cannot write output: " + sysError(errno));
    const char* p = bytes.data();
    size_t left = bytes.size();
    while (left > 0) {
        const ssize_t n = ::write(fd, p, std::min<size_t>(left, size_t{1} << 30));
        if (n < 0) {
            if (errno == EINTR) continue;
            const int err = errno;
            ::close(fd);
            throw InputError(SourceLoc{where}, fmt::format("cannot write output ({} of {} bytes written): {}",
                                                           bytes.size() - left, bytes.size(), sysError(err)));
        }
        p += n;
        left -= static_cast<size_t>(n);
    }
    // Delayed allocation and network file systems report ENOSPC / EIO only here.
    if (::fdatasync(fd) != 0 && errno != EINVAL && errno != EROFS) {
        const int err = errno;
        ::close(fd);
        throw InputError(SourceLoc{where}, "cannot write output (flushing to disk failed): " + sysError(err));
    }
    if (::close(fd) != 0)
        throw InputError(SourceLoc{where}, "cannot write output (closing the file failed): " + sysError(errno));
}

void AtomicOutput::commit() {
    checkOutputTarget(target_);
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.m);
    if (r.setActive) {
        // A target staged earlier in this set is superseded by the new content.
        for (auto it = r.staged.begin(); it != r.staged.end(); ++it)
            if (it->target == target_.string()) {
                ::unlink(it->temp.c_str());
                r.staged.erase(it);
                break;
            }
        r.staged.push_back({temp_.string(), target_.string()});
    } else if (::rename(temp_.c_str(), target_.c_str()) != 0) {
        throw InputError(SourceLoc{target_.string()}, "cannot write output: " + sysError(errno));
    }
    eraseValue(r.temps, temp_.string());
    committed_ = true;
}

void writeFileAtomic(const fs::path& target, std::string_view bytes) {
    AtomicOutput out(target);
    out.write(bytes);
    out.commit();
}

// ---------------------------------------------------------------------------------------------
// Output sets

namespace {
// Renames every staged temporary; on failure leaves the lists as they are (the caller rolls back).
void publishLocked(Registry& r) {
    while (!r.staged.empty()) {
        const Registry::Staged s = r.staged.front();
        struct stat st;
        if (::lstat(s.target.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
            throw InputError(SourceLoc{s.target}, fmt::format("refusing to write output: {} is in the way; Littoral "
                                                              "replaces only regular files",
                                                              kindOf(st.st_mode)));
        if (::rename(s.temp.c_str(), s.target.c_str()) != 0)
            throw InputError(SourceLoc{s.target}, "cannot write output: " + sysError(errno));
        r.published.push_back(s.target);
        r.staged.erase(r.staged.begin());
    }
}
}  // namespace

namespace {
// The process id in a lock file, or 0 if it holds none.
long lockOwner(const std::string& path) {
    std::ifstream f(path);
    long pid = 0;
    if (!(f >> pid) || pid <= 0) return 0;
    return pid;
}
// Whether `pid` is a process that can still write: one that exists (kill 0 succeeds, or it is another
// user's) and is not a zombie. A killed command whose parent exited is reparented to PID 1, and in a
// container PID 1 often never reaps it: its lock would otherwise be held for ever (seen in CI after
// mpirun was stopped with SIGTERM: the resumed run was refused by the killed rank's zombie).
bool processRuns(long pid) {
    if (pid <= 0 || (::kill(static_cast<pid_t>(pid), 0) != 0 && errno != EPERM)) return false;
    std::ifstream stat(fmt::format("/proc/{}/stat", pid));
    std::string text;
    if (!std::getline(stat, text)) return true;  // no /proc: trust kill
    // "pid (comm) S ...": the state follows the last ')' (comm may hold spaces and parentheses).
    const size_t close = text.rfind(')');
    return close == std::string::npos || close + 2 >= text.size() || (text[close + 2] != 'Z' && text[close + 2] != 'X');
}
}  // namespace

namespace {

// Removes the temporaries "<stem>.tmp-<pid>-<n><ext>" that process `pid` (which no longer runs)
// left under `dir` when it was killed before it could rename or remove them. Returns how many.
size_t removeTemporariesOf(const fs::path& dir, long pid) {
    const std::string tag = fmt::format(".tmp-{}-", pid);
    size_t n = 0;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec)) {
        const std::string name = it->path().filename().string();
        const size_t at = name.find(tag);
        if (at == std::string::npos || !it->is_regular_file(ec) || it->is_symlink(ec)) continue;
        const size_t digits = at + tag.size();
        if (digits >= name.size() || !std::isdigit(static_cast<unsigned char>(name[digits]))) continue;
        std::error_code rm;
        if (fs::remove(it->path(), rm)) ++n;
    }
    return n;
}

}  // namespace

OutputFolderLock::OutputFolderLock(const fs::path& dir, std::string_view option) {
    checkOutputFolder(dir, option);  // the same messages as before any work (a file in the way, read-only)
    if (!isRootRank()) return;       // an MPI run's rank 0 holds the lock for all its ranks (core/ranks.h)
    createOutputFolder(dir, option);
    path_ = (dir.empty() ? fs::path(".") : dir).string() + "/" + kFileName;
    const std::string prefix = option.empty() ? std::string() : std::string(option) + ": ";
    for (int attempt = 0; attempt < 2; ++attempt) {
        const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd >= 0) {
            const std::string pid = std::to_string(static_cast<long>(::getpid())) + "\n";
            const bool ok = ::write(fd, pid.data(), pid.size()) == static_cast<ssize_t>(pid.size());
            ::close(fd);
            if (!ok) {
                ::unlink(path_.c_str());
                throw InputError(SourceLoc{dir.string()}, prefix + "cannot write the folder's lock file: " + sysError(errno));
            }
            Registry& r = registry();
            std::lock_guard<std::mutex> lock(r.m);
            r.locks.push_back(path_);
            return;
        }
        if (errno != EEXIST)
            throw InputError(SourceLoc{dir.string()}, prefix + "cannot create the folder's lock file: " + sysError(errno));
        const long owner = lockOwner(path_);
        if (owner == static_cast<long>(::getpid()))
            throw InternalError(fmt::format("{}: this process already holds the lock", path_));
        if (processRuns(owner))
            throw InputError(SourceLoc{dir.string()},
                             fmt::format("{}another littoral command (process {}) is writing into this folder; wait "
                                         "for it to finish or choose another folder",
                                         prefix, owner));
        const size_t litter = owner > 0 ? removeTemporariesOf(dir, owner) : 0;
        log::warn("{}{}: taking over the lock of process {}, which no longer runs{}", prefix, dir.string(),
                  owner > 0 ? std::to_string(owner) : std::string("(unknown)"),
                  litter ? fmt::format(" (removed {} unfinished temporary file(s) it left)", litter) : std::string());
        ::unlink(path_.c_str());
    }
    throw InputError(SourceLoc{dir.string()}, prefix + "another command took the folder's lock at the same time");
}

OutputFolderLock::~OutputFolderLock() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.m);
    if (std::find(r.locks.begin(), r.locks.end(), path_) == r.locks.end()) return;  // removed by a rollback
    ::unlink(path_.c_str());
    eraseValue(r.locks, path_);
}

OutputSet::OutputSet() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.m);
    if (r.setActive) throw InternalError("output sets do not nest");
    r.setActive = true;
}

OutputSet::~OutputSet() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.m);
    if (!r.setActive) return;  // committed
    rollbackLocked(r);
    r.setActive = false;
}

void OutputSet::commit() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.m);
    publishLocked(r);
    r.published.clear();
    r.createdDirs.clear();
    r.setActive = false;
}

OutputSetPause::OutputSetPause() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.m);
    wasActive_ = r.setActive;
    r.setActive = false;
}

OutputSetPause::~OutputSetPause() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.m);
    r.setActive = wasActive_;
}

bool OutputSet::active() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.m);
    return r.setActive;
}

void publishStagedOutputs() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.m);
    if (!r.setActive) return;
    publishLocked(r);
    r.published.clear();
    r.createdDirs.clear();
}

void exposeStagedOutputs() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.m);
    if (!r.setActive) return;
    publishLocked(r);  // the renamed targets stay in `published` and the folders in `createdDirs`
}

void installInterruptCleanup() {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &set, nullptr);
    std::thread([set] {
        int sig = 0;
        while (sigwait(&set, &sig) != 0) {
        }
        Registry& r = registry();
        r.m.lock();  // held until _exit: nothing is created or renamed after this point
        const size_t n = r.temps.size() + r.staged.size() + r.published.size();
        rollbackLocked(r);
        const std::string msg = fmt::format("littoral: interrupted by {}; removed {} partial output file(s)\n",
                                            sig == SIGINT ? "SIGINT" : "SIGTERM", n);
        [[maybe_unused]] const ssize_t w = ::write(2, msg.data(), msg.size());
        ::_exit(128 + sig);
    }).detach();
}

// ---------------------------------------------------------------------------------------------
// Reading

void requireRegularInputFile(const fs::path& path, std::string_view what) {
    struct stat st;
    const std::string w(what);
    if (::stat(path.c_str(), &st) != 0) {
        if (errno == ENOENT) throw InputError(SourceLoc{path.string()}, w + " does not exist");
        throw InputError(SourceLoc{path.string()}, fmt::format("cannot open {}: {}", w, sysError(errno)));
    }
    if (S_ISDIR(st.st_mode)) throw InputError(SourceLoc{path.string()}, fmt::format("is a folder, not a {}", w));
    if (!S_ISREG(st.st_mode))
        throw InputError(SourceLoc{path.string()},
                         fmt::format("is {}, not a regular file; a {} must be a regular file", kindOf(st.st_mode), w));
    noteInputStat(st, path);
}

std::string readTextFile(const fs::path& path) {
    requireRegularInputFile(path, "file");
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (!ec) requireMemory(static_cast<double>(size), fmt::format("reading {} ({} bytes) would", path.string(), size),
                           SourceLoc{path.string()});
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError(SourceLoc{path.string()}, "cannot open file for reading: " + sysError(errno));
    std::ostringstream ss;
    ss << f.rdbuf();
    if (f.bad()) throw InputError(SourceLoc{path.string()}, "cannot read file: " + sysError(errno));
    return ss.str();
}

}  // namespace littoral

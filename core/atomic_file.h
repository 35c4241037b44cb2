#pragma once
// Writing outputs so that a failed run never leaves a truncated file over a good one:
// everything is written to "<name>.tmp-<pid>" beside the target and renamed on commit().
// If the AtomicOutput is destroyed without commit() (an exception unwound), the temporary is
// removed and the target is untouched.
#include <filesystem>
#include <functional>
#include <string>

namespace littoral {

class AtomicOutput {
public:
    explicit AtomicOutput(std::filesystem::path target);
    ~AtomicOutput();
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;

    const std::filesystem::path& tempPath() const { return temp_; }
    const std::filesystem::path& target() const { return target_; }
    void commit();  // rename temp -> target (atomic on one filesystem)

private:
    std::filesystem::path target_, temp_;
    bool committed_ = false;
};

// Convenience: write text to `target` atomically.
void writeTextFileAtomic(const std::filesystem::path& target, const std::string& text);
// Convenience: let `writer` fill the temporary path, then commit.
void writeFileAtomic(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path& temp)>& writer);

// Reads a whole file; InputError naming the path if it cannot be read.
std::string readTextFile(const std::filesystem::path& path);

}  // namespace littoral

// TelemetryCsvWriter: writes the cache telemetry log, one CSV row per frame, to a temporary
// file that becomes the destination only on close(), so the log is never seen half-written
// and an aborted run leaves no truncated log under the destination's name.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/FrameTelemetry.h"

#include <cstdint>
#include <filesystem>
#include <memory>

namespace terrain::runtime {

/// The CSV: a header row of the column names in kTelemetryColumns order, then one row per
/// write(), '\n' line ends, no quoting (no field contains a comma). Counts are decimal
/// integers; doubles are written in the shortest form that reads back as the same double
/// (std::to_chars), e.g. 16.712345 or 1e-05, so time_s keeps full precision over long runs;
/// NaN is an empty field, infinities "inf" / "-inf".
///
/// Move-only; destroying an open writer (or moving another onto it) removes its temporary
/// file. Not thread-safe: one thread at a time (the render thread in the viewer).
class TelemetryCsvWriter {
public:
    /// Creates the temporary file next to `path` (see AtomicFile) and writes the header
    /// row. Fails, naming `path`, when the folder is missing or not writable.
    static Result<TelemetryCsvWriter> create(const std::filesystem::path& path);

    TelemetryCsvWriter(TelemetryCsvWriter&& other) noexcept;
    TelemetryCsvWriter& operator=(TelemetryCsvWriter&& other) noexcept;
    TelemetryCsvWriter(const TelemetryCsvWriter&) = delete;
    TelemetryCsvWriter& operator=(const TelemetryCsvWriter&) = delete;
    ~TelemetryCsvWriter();

    /// Appends one row. Never allocates (formats into a fixed buffer, writes through a
    /// stdio buffer allocated by create()). A write error is kept and reported by close().
    /// Only while isOpen().
    void write(const FrameTelemetry& frame);

    /// Flushes, closes and renames the temporary file onto path(), replacing an existing
    /// file. On failure (a write error seen by any write(), or the rename) the temporary
    /// file is removed and the error names path(). The writer is closed either way. Only
    /// while isOpen().
    Status close();

    bool isOpen() const { return m_state != nullptr; }
    /// The destination given to create().
    const std::filesystem::path& path() const { return m_path; }
    /// Data rows written so far (the header not counted).
    std::uint64_t rowCount() const { return m_rowCount; }

private:
    struct State;  // the FILE*, the AtomicFile and the buffers, at a stable address
    TelemetryCsvWriter(std::filesystem::path path, std::unique_ptr<State> state);

    std::filesystem::path m_path;
    std::unique_ptr<State> m_state;  // null once closed or moved from
    std::uint64_t m_rowCount = 0;
};

}  // namespace terrain::runtime

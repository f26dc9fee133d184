// CSV writer of the cache telemetry log (see TelemetryCsvWriter.h). Rows are formatted with
// std::to_chars into a fixed buffer and written through stdio with a buffer of our own, so
// write() does no allocation in steady state.
#include "terrain/runtime/TelemetryCsvWriter.h"

#include "terrain/base/Assert.h"
#include "terrain/base/AtomicFile.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string_view>
#include <system_error>
#include <utility>

namespace terrain::runtime {

namespace {

// The longest field std::to_chars writes: 20 digits for a uint64; 24 characters for the
// shortest round-trip form of a double ("-2.2250738585072014e-308").
constexpr std::size_t kMaxFieldChars = 24;
constexpr std::size_t kMaxNameChars = 64;
constexpr std::size_t kRowBufferBytes =
    kTelemetryColumns.size() * (std::max(kMaxFieldChars, kMaxNameChars) + 1) + 1;
// Rows are ~200 bytes; 64 KiB means a write(2) every few hundred frames.
constexpr std::size_t kStdioBufferBytes = 64 * 1024;

constexpr bool namesFit() {
    for (const TelemetryColumn& column : kTelemetryColumns) {
        if (column.name.size() > kMaxNameChars) return false;
    }
    return true;
}
static_assert(namesFit(), "a telemetry column name is longer than kMaxNameChars");

}  // namespace

struct TelemetryCsvWriter::State {
    explicit State(AtomicFile&& atomicFile) : file(std::move(atomicFile)) {}
    State(const State&) = delete;
    State& operator=(const State&) = delete;
    ~State() {
        // Close before `file` (destroyed after this body) removes the temporary file.
        if (stream != nullptr) std::fclose(stream);
    }

    // Appends the row in `row` (up to `end`) to the stream, keeping the first error.
    void put(const char* end) {
        if (writeErrno != 0) return;
        const std::size_t size = static_cast<std::size_t>(end - row.data());
        errno = 0;  // so a short write without an errno is reported as EIO, not a stale one
        if (std::fwrite(row.data(), 1, size, stream) != size) writeErrno = errno ? errno : EIO;
    }

    AtomicFile file;
    std::FILE* stream = nullptr;
    int writeErrno = 0;  // first error of a write, reported by close()
    std::array<char, kRowBufferBytes> row{};
    std::array<char, kStdioBufferBytes> stdioBuffer{};
};

Result<TelemetryCsvWriter> TelemetryCsvWriter::create(const std::filesystem::path& path) {
    Result<AtomicFile> file = AtomicFile::create(path);
    if (!file) return file.error();
    auto state = std::make_unique<State>(std::move(file).value());
    state->stream = std::fopen(state->file.temporaryPath().c_str(), "wb");
    if (state->stream == nullptr) {
        return Error{fmt::format("{}: cannot open the temporary file '{}' for writing: {}",
                                 path.string(), state->file.temporaryPath().string(),
                                 std::strerror(errno))};
    }
    // Our buffer, so that stdio does not allocate one lazily in the first write().
    std::array<char, kStdioBufferBytes>& buffer = state->stdioBuffer;
    if (std::setvbuf(state->stream, buffer.data(), _IOFBF, buffer.size()) != 0) {
        return Error{fmt::format("{}: cannot set up a write buffer", path.string())};
    }

    char* out = state->row.data();
    for (const TelemetryColumn& column : kTelemetryColumns) {
        if (out != state->row.data()) *out++ = ',';
        out = std::copy(column.name.begin(), column.name.end(), out);
    }
    *out++ = '\n';
    state->put(out);
    if (state->writeErrno != 0) {
        return Error{fmt::format("{}: cannot write the header row: {}", path.string(),
                                 std::strerror(state->writeErrno))};
    }
    return TelemetryCsvWriter(path, std::move(state));
}

TelemetryCsvWriter::TelemetryCsvWriter(std::filesystem::path path, std::unique_ptr<State> state)
    : m_path(std::move(path)), m_state(std::move(state)) {}

TelemetryCsvWriter::TelemetryCsvWriter(TelemetryCsvWriter&& other) noexcept = default;
TelemetryCsvWriter& TelemetryCsvWriter::operator=(TelemetryCsvWriter&& other) noexcept = default;
TelemetryCsvWriter::~TelemetryCsvWriter() = default;

void TelemetryCsvWriter::write(const FrameTelemetry& frame) {
    TERRAIN_ASSERT(m_state, "TelemetryCsvWriter::write() on a closed writer");
    State& state = *m_state;
    char* out = state.row.data();
    char* const last = state.row.data() + state.row.size();
    bool first = true;
    for (const TelemetryColumn& column : kTelemetryColumns) {
        if (!first) *out++ = ',';
        first = false;
        std::to_chars_result result{out, std::errc()};
        if (column.kind == TelemetryValueKind::Count) {
            result = std::to_chars(out, last, frame.*column.count);
        } else {
            const double value = frame.*column.real;
            if (std::isnan(value)) continue;  // NaN: an empty field
            // No format argument: the shortest representation that round-trips.
            result = std::to_chars(out, last, value);
        }
        TERRAIN_ASSERT(result.ec == std::errc(), "telemetry row buffer too small");
        out = result.ptr;
    }
    *out++ = '\n';
    state.put(out);
    ++m_rowCount;
}

Status TelemetryCsvWriter::close() {
    TERRAIN_ASSERT(m_state, "TelemetryCsvWriter::close() on a closed writer");
    // Released when this returns: on any failure ~State removes the temporary file.
    const std::unique_ptr<State> state = std::move(m_state);
    int error = state->writeErrno;
    errno = 0;
    if (error == 0 && std::fflush(state->stream) != 0) error = errno ? errno : EIO;
    if (std::fclose(std::exchange(state->stream, nullptr)) != 0 && error == 0) {
        error = errno ? errno : EIO;
    }
    if (error != 0) {
        return Error{fmt::format("{}: cannot write the telemetry log: {}", m_path.string(),
                                 std::strerror(error))};
    }
    return state->file.commit();
}

}  // namespace terrain::runtime

// TelemetryCsvWriter: the header is exactly the documented column list, rows read back
// exactly (doubles round-trip), NaN is an empty field, the file appears only on close(),
// an unclosed writer leaves nothing, and errors name the path.
#include "terrain/runtime/TelemetryCsvWriter.h"

#include "TempFolder.h"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace terrain::runtime {
namespace {

// The user-facing column list of docs/telemetry.md, spelled out so that a rename, a removal
// or a reordering fails here. Append new columns at the end (and to the docs).
constexpr const char* kExpectedHeader =
    "frame,time_s,frame_ms,"
    "requests_made,requests_cancelled,requests_completed,requests_failed,"
    "queue_depth,io_in_flight,"
    "cpu_cache_hits,cpu_cache_misses,cpu_cache_evictions,cpu_cache_entries,cpu_cache_bytes,"
    "cpu_cache_budget_bytes,"
    "gpu_layers_used,gpu_layers_free,gpu_evictions,gpu_uploads,gpu_upload_bytes,"
    "gpu_uploads_deferred,gpu_ring_stalls,"
    "loads_resident,load_latency_p50_ms,load_latency_p95_ms,load_latency_p99_ms,"
    "disk_read_bytes,stored_bytes_read,faults_total,"
    "patches_drawn,patches_culled,triangles,draw_calls,lod_update_us,gpu_ms,lod_splits,"
    "lod_merges,lod_waiting_splits,patches_horizon_culled,"
    "imagery_requests_made,imagery_requests_cancelled,imagery_requests_completed,"
    "imagery_requests_failed,imagery_requests_pending,imagery_tiles_resident,imagery_gpu_bytes,"
    "imagery_gpu_uploads,imagery_gpu_upload_bytes,imagery_gpu_evictions,"
    "imagery_cpu_cache_entries,imagery_cpu_cache_bytes,imagery_loads_resident,"
    "imagery_load_latency_p50_ms,imagery_load_latency_p95_ms,imagery_faults_total,"
    "http_requests,http_retries,http_files_fetched,http_fetched_bytes,http_not_modified,"
    "http_cache_hits,http_stale_served";

std::string readFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
        const std::size_t end = text.find(separator, start);
        parts.push_back(text.substr(start, end - start));
        if (end == std::string::npos) return parts;
        start = end + 1;
    }
}

std::vector<std::filesystem::path> filesIn(const std::filesystem::path& folder) {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
        files.push_back(entry.path());
    }
    return files;
}

// A frame whose every field differs, with doubles that need all 17 significant digits.
FrameTelemetry distinctFrame(std::uint64_t seed) {
    FrameTelemetry frame;
    std::uint64_t next = seed * 1000;
    for (const TelemetryColumn& column : telemetryColumns()) {
        ++next;
        if (column.kind == TelemetryValueKind::Count) {
            frame.*column.count = next * 1'000'003;
        } else {
            frame.*column.real = static_cast<double>(next) / 3.0;
        }
    }
    frame.frame = std::numeric_limits<std::uint64_t>::max() - seed;  // the widest count
    frame.timeS = 86'400.123456789 + static_cast<double>(seed);      // a day into a run
    frame.frameMs = 16.712345;
    return frame;
}

// Parses one data row back into a FrameTelemetry; empty real fields become NaN.
FrameTelemetry parseRow(const std::string& line) {
    const std::vector<std::string> fields = split(line, ',');
    EXPECT_EQ(fields.size(), telemetryColumns().size()) << line;
    FrameTelemetry frame;
    for (std::size_t i = 0; i < fields.size() && i < telemetryColumns().size(); ++i) {
        const TelemetryColumn& column = telemetryColumns()[i];
        const std::string& field = fields[i];
        const char* end = field.data() + field.size();
        if (column.kind == TelemetryValueKind::Count) {
            std::uint64_t value = 0;
            const auto [ptr, ec] = std::from_chars(field.data(), end, value);
            EXPECT_TRUE(ec == std::errc() && ptr == end) << column.name << " = '" << field << "'";
            frame.*column.count = value;
        } else if (field.empty()) {
            frame.*column.real = std::numeric_limits<double>::quiet_NaN();
        } else {
            double value = 0.0;
            const auto [ptr, ec] = std::from_chars(field.data(), end, value);
            EXPECT_TRUE(ec == std::errc() && ptr == end) << column.name << " = '" << field << "'";
            frame.*column.real = value;
        }
    }
    return frame;
}

void expectSameFrame(const FrameTelemetry& actual, const FrameTelemetry& expected) {
    for (const TelemetryColumn& column : telemetryColumns()) {
        if (column.kind == TelemetryValueKind::Count) {
            EXPECT_EQ(actual.*column.count, expected.*column.count) << column.name;
        } else if (std::isnan(expected.*column.real)) {
            EXPECT_TRUE(std::isnan(actual.*column.real)) << column.name;
        } else {
            EXPECT_EQ(actual.*column.real, expected.*column.real) << column.name;  // exact
        }
    }
}

TEST(TelemetryCsvWriter, HeaderIsTheDocumentedColumnList) {
    test::TempFolder folder;
    const std::filesystem::path path = folder.path() / "telemetry.csv";
    Result<TelemetryCsvWriter> writer = TelemetryCsvWriter::create(path);
    ASSERT_TRUE(writer) << writer.error().message;
    ASSERT_TRUE(writer.value().close());
    EXPECT_EQ(readFile(path), std::string(kExpectedHeader) + "\n");
}

TEST(TelemetryCsvWriter, EveryColumnIsDocumented) {
    const std::string docs =
        readFile(std::filesystem::path(TERRAIN_SOURCE_DIR) / "docs" / "telemetry.md");
    ASSERT_FALSE(docs.empty()) << "docs/telemetry.md is missing";
    for (const TelemetryColumn& column : telemetryColumns()) {
        EXPECT_NE(docs.find("| `" + std::string(column.name) + "` |"), std::string::npos)
            << column.name << " has no row in the column table of docs/telemetry.md";
    }
}

TEST(TelemetryCsvWriter, RowsReadBackExactly) {
    test::TempFolder folder;
    const std::filesystem::path path = folder.path() / "telemetry.csv";
    Result<TelemetryCsvWriter> created = TelemetryCsvWriter::create(path);
    ASSERT_TRUE(created) << created.error().message;
    TelemetryCsvWriter writer = std::move(created).value();

    std::vector<FrameTelemetry> frames = {distinctFrame(1), distinctFrame(2), FrameTelemetry()};
    frames[1].frameMs = 0.1 + 0.2;  // 0.30000000000000004: needs every digit
    frames[1].loadLatencyP99Ms = 1e-7;
    frames[1].loadLatencyP95Ms = 123456789.5;
    for (const FrameTelemetry& frame : frames) writer.write(frame);
    EXPECT_EQ(writer.rowCount(), frames.size());
    ASSERT_TRUE(writer.close());

    const std::string text = readFile(path);
    ASSERT_FALSE(text.empty());
    EXPECT_EQ(text.back(), '\n');
    std::vector<std::string> lines = split(text.substr(0, text.size() - 1), '\n');
    ASSERT_EQ(lines.size(), frames.size() + 1);
    EXPECT_EQ(lines[0], kExpectedHeader);
    for (std::size_t i = 0; i < frames.size(); ++i) {
        SCOPED_TRACE(lines[i + 1]);
        expectSameFrame(parseRow(lines[i + 1]), frames[i]);
    }
    // Plain decimal where that is the shortest form: readable without a parser.
    EXPECT_NE(lines[1].find(",86401.123456789,16.712345,"), std::string::npos) << lines[1];
}

TEST(TelemetryCsvWriter, NaNIsAnEmptyField) {
    test::TempFolder folder;
    const std::filesystem::path path = folder.path() / "telemetry.csv";
    Result<TelemetryCsvWriter> writer = TelemetryCsvWriter::create(path);
    ASSERT_TRUE(writer) << writer.error().message;
    FrameTelemetry frame;  // latencies default to NaN: no load yet
    frame.frame = 7;
    frame.timeS = 0.5;
    frame.frameMs = std::numeric_limits<double>::quiet_NaN();
    frame.loadsResident = 3;
    frame.diskReadBytes = 4096;
    writer.value().write(frame);
    ASSERT_TRUE(writer.value().close());

    const std::vector<std::string> lines = split(readFile(path), '\n');
    ASSERT_GE(lines.size(), 2u);
    EXPECT_EQ(lines[1],
              "7,0.5,,"          // frame, time_s, frame_ms
              "0,0,0,0,0,0,"     // requests, queue, in flight
              "0,0,0,0,0,0,"     // CPU cache
              "0,0,0,0,0,0,0,"   // GPU pool
              "3,,,,"            // loads_resident, three empty percentiles
              "4096,0,0,0,0,"    // disk, stored bytes, faults, patches
              "0,0,,,0,0,0,0,"   // triangles, draw calls, two empty times, splits, merges,
                                 // waiting splits, horizon
              "0,0,0,0,0,"       // imagery requests, pending
              "0,0,0,0,0,0,0,"   // imagery GPU and CPU
              "0,,,0,"           // imagery loads, two empty percentiles, faults
              "0,0,0,0,0,0,0");  // HTTP
}

TEST(TelemetryCsvWriter, FileAppearsOnlyOnClose) {
    test::TempFolder folder;
    const std::filesystem::path path = folder.path() / "telemetry.csv";
    Result<TelemetryCsvWriter> writer = TelemetryCsvWriter::create(path);
    ASSERT_TRUE(writer) << writer.error().message;
    EXPECT_TRUE(writer.value().isOpen());
    EXPECT_EQ(writer.value().path(), path);
    writer.value().write(distinctFrame(1));
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_EQ(filesIn(folder.path()).size(), 1u);  // the temporary file

    ASSERT_TRUE(writer.value().close());
    EXPECT_FALSE(writer.value().isOpen());
    EXPECT_TRUE(std::filesystem::exists(path));
    EXPECT_EQ(filesIn(folder.path()), std::vector<std::filesystem::path>{path});
}

TEST(TelemetryCsvWriter, CloseReplacesAnExistingFile) {
    test::TempFolder folder;
    const std::filesystem::path path = folder.path() / "telemetry.csv";
    std::ofstream(path) << "an older log\n";
    Result<TelemetryCsvWriter> writer = TelemetryCsvWriter::create(path);
    ASSERT_TRUE(writer) << writer.error().message;
    EXPECT_EQ(readFile(path), "an older log\n");  // untouched until close()
    ASSERT_TRUE(writer.value().close());
    EXPECT_EQ(readFile(path), std::string(kExpectedHeader) + "\n");
}

TEST(TelemetryCsvWriter, DestroyingWithoutCloseLeavesNoFile) {
    test::TempFolder folder;
    const std::filesystem::path path = folder.path() / "telemetry.csv";
    {
        Result<TelemetryCsvWriter> writer = TelemetryCsvWriter::create(path);
        ASSERT_TRUE(writer) << writer.error().message;
        for (std::uint64_t i = 0; i < 5000; ++i) writer.value().write(distinctFrame(i));
    }
    EXPECT_TRUE(filesIn(folder.path()).empty());
}

TEST(TelemetryCsvWriter, MovingKeepsOneOwnerAndDiscardsTheOverwrittenLog) {
    test::TempFolder folder;
    Result<TelemetryCsvWriter> first = TelemetryCsvWriter::create(folder.path() / "a.csv");
    Result<TelemetryCsvWriter> second = TelemetryCsvWriter::create(folder.path() / "b.csv");
    ASSERT_TRUE(first && second);
    TelemetryCsvWriter writer = std::move(first).value();
    writer.write(distinctFrame(1));
    writer = std::move(second).value();  // a.csv's temporary file goes with it
    EXPECT_EQ(filesIn(folder.path()).size(), 1u);
    writer.write(distinctFrame(2));
    ASSERT_TRUE(writer.close());
    EXPECT_EQ(filesIn(folder.path()), std::vector<std::filesystem::path>{folder.path() / "b.csv"});
    EXPECT_EQ(split(readFile(folder.path() / "b.csv"), '\n').size(), 3u);  // header, row, ""
}

TEST(TelemetryCsvWriter, MissingFolderIsAnErrorNamingThePath) {
    test::TempFolder folder;
    const std::filesystem::path path = folder.path() / "no-such-folder" / "telemetry.csv";
    Result<TelemetryCsvWriter> writer = TelemetryCsvWriter::create(path);
    ASSERT_FALSE(writer);
    EXPECT_NE(writer.error().message.find(path.string()), std::string::npos)
        << writer.error().message;
    EXPECT_TRUE(filesIn(folder.path()).empty());
}

TEST(TelemetryCsvWriter, FolderAsPathIsAnErrorNamingThePath) {
    test::TempFolder folder;
    Result<TelemetryCsvWriter> writer = TelemetryCsvWriter::create(folder.path());
    ASSERT_FALSE(writer);
    EXPECT_NE(writer.error().message.find(folder.path().string()), std::string::npos)
        << writer.error().message;
}

TEST(TelemetryCsvWriter, FailedRenameIsAnErrorNamingThePathAndLeavesNoTemporaryFile) {
    test::TempFolder folder;
    const std::filesystem::path path = folder.path() / "telemetry.csv";
    Result<TelemetryCsvWriter> writer = TelemetryCsvWriter::create(path);
    ASSERT_TRUE(writer) << writer.error().message;
    // A non-empty folder now occupies the destination: rename(2) cannot replace it.
    std::filesystem::create_directories(path / "occupied");
    const Status closed = writer.value().close();
    ASSERT_FALSE(closed);
    EXPECT_NE(closed.error().message.find(path.string()), std::string::npos)
        << closed.error().message;
    EXPECT_FALSE(writer.value().isOpen());
    EXPECT_EQ(filesIn(folder.path()), std::vector<std::filesystem::path>{path});
}

}  // namespace
}  // namespace terrain::runtime

// terrain-view as a user runs it, in a virtual X display (Xvfb, Mesa's llvmpipe): it
// records a path while playing one, plays the recording, and writes a screenshot in which
// terrain and the overlay can both be found; its telemetry log and JSON summary are right;
// and a missing or broken pyramid, a missing path file, an unwritable output folder, no
// display and no OpenGL 4.5 each give a message and exit status 1, never a crash.
#include "terrain/build/GlobePyramidBuilder.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/CameraPath.h"
#include "terrain/runtime/FlightPath.h"
#include "terrain/runtime/TerrainGeometry.h"

#include "GeographicFunctionDem.h"
#include "TempFolder.h"
#include "XvfbServer.h"

#include <OpenImageIO/imageio.h>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace terrain {
namespace {

namespace fs = std::filesystem;

const std::string kViewer = TERRAIN_VIEW;
const std::string kPyramid = std::string(TERRAIN_TOOLS_OUT) + "/procedural.pyramid";
const std::string kXvfb = TERRAIN_XVFB;  // empty when CMake did not find it

struct ToolRun {
    int status = -1;  ///< exit status; -1 when killed by a signal (a crash)
    std::string out;  ///< stdout
    std::string err;  ///< stderr
};

// Runs a shell command, capturing stdout and stderr.
ToolRun run(const std::string& command, const test::TempFolder& folder) {
    ToolRun result;
    const std::string errFile = folder.file("stderr.txt");
    FILE* pipe = ::popen((command + " 2>" + errFile).c_str(), "r");
    if (pipe == nullptr) return result;
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) result.out.append(buffer, n);
    const int status = ::pclose(pipe);
    result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream err(errFile);
    result.err.assign(std::istreambuf_iterator<char>(err), {});
    return result;
}

// This test process's virtual X server, started on first use (XvfbServer.h: Xvfb picks a
// free display itself, and the status below is the viewer's own, not a wrapper's).
const test::XvfbServer& xServer() {
    static const test::XvfbServer server(kXvfb);
    return server;
}

// The viewer on that display.
ToolRun runViewer(const std::string& arguments, const test::TempFolder& folder,
                  const std::string& environment = "") {
    if (xServer().display().empty()) {
        ToolRun failed;
        failed.err = "no X server: " + xServer().error();
        return failed;
    }
    return run(
        "env DISPLAY=" + xServer().display() + " " + environment + " " + kViewer + " " + arguments,
        folder);
}

std::string describe(const ToolRun& r) {
    return "exit status " + std::to_string(r.status) + "\nstderr:\n" + r.err + "\nstdout:\n" +
           r.out.substr(0, 2000);
}

nlohmann::json summaryOf(const ToolRun& r) {
    const nlohmann::json json = nlohmann::json::parse(r.out, nullptr, false);
    EXPECT_FALSE(json.is_discarded()) << describe(r);
    return json;
}

struct Image {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::vector<std::uint8_t> pixels;
    const std::uint8_t* at(int x, int y) const {
        return &pixels[(static_cast<std::size_t>(y) * width + x) * channels];
    }
};

Image readPng(const std::string& path) {
    Image image;
    auto input = OIIO::ImageInput::open(path);
    if (!input) return image;
    const OIIO::ImageSpec& spec = input->spec();
    image.width = spec.width;
    image.height = spec.height;
    image.channels = spec.nchannels;
    image.pixels.resize(static_cast<std::size_t>(image.width) * image.height * image.channels);
    if (!input->read_image(0, 0, 0, image.channels, OIIO::TypeDesc::UINT8, image.pixels.data())) {
        image = {};
    }
    return image;
}

struct Rect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) × [y0, y1)
    bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};

// The clear colour of TerrainStyle::skyColor {0.72, 0.80, 0.90} in 8 bits.
bool isSky(const std::uint8_t* p) {
    return std::abs(p[0] - 184) <= 2 && std::abs(p[1] - 204) <= 2 && std::abs(p[2] - 230) <= 2;
}

int difference(const std::uint8_t* a, const std::uint8_t* b) {
    return std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]);
}

class ViewerTool : public ::testing::Test {
protected:
    void SetUp() override {
        ASSERT_FALSE(kXvfb.empty())
            << "Xvfb was not found when CMake ran: install the Debian package xvfb "
               "(scripts/setup.sh does) and re-run CMake";
        ASSERT_TRUE(fs::exists(fs::path(kPyramid) / "manifest.json"))
            << kPyramid
            << " is missing: the procedural_pyramid fixture (tools.build_procedural) "
               "builds it";
    }
    test::TempFolder m_folder;
};

TEST_F(ViewerTool, RecordsAPathWhilePlayingOneAndLogsTelemetry) {
    auto manifest = io::readManifest(kPyramid);
    ASSERT_TRUE(manifest) << manifest.error().message;
    const runtime::TerrainGeometry geometry(manifest.value());
    const runtime::CameraPath flight = runtime::CameraPath::defaultFor(geometry, 4.0);
    const std::string flightFile = m_folder.file("flight.camera.json");
    ASSERT_TRUE(flight.save(flightFile));

    // 40 frames at 10 flight-frames per second: 3.9 s of the 4 s flight.
    const std::string recorded = m_folder.file("recorded.camera.json");
    const std::string csv = m_folder.file("telemetry.csv");
    const ToolRun r =
        runViewer(kPyramid + " --path " + flightFile + " --record " + recorded + " --telemetry " +
                      csv + " --frames 40 --fps 10 --width 320 --height 240 --json",
                  m_folder);
    ASSERT_EQ(r.status, 0) << describe(r);
    const nlohmann::json summary = summaryOf(r);
    EXPECT_EQ(summary["frames"], 40);
    EXPECT_EQ(summary["gl_errors"], 0);
    EXPECT_EQ(summary["draw_calls_last"], 1);
    EXPECT_GT(summary["patches_drawn_last"].get<int>(), 0);
    EXPECT_NEAR(summary["path_time_s"].get<double>(), 3.9, 1e-9);
    EXPECT_EQ(summary["paths_recorded"], nlohmann::json::array({recorded}));
    EXPECT_EQ(summary["telemetry_csv"], nlohmann::json::array({csv}));
    EXPECT_EQ(summary["gl"]["major"], 4);

    // The recording passes through the flight at its keyframe times.
    auto path = runtime::CameraPath::load(recorded);
    ASSERT_TRUE(path) << path.error().message;
    const auto& keyframes = path.value().keyframes();
    // Frames every 0.1 s: a keyframe every third frame (0.3 s ≥ kIntervalS), then the last.
    EXPECT_EQ(keyframes.size(), 14u);
    EXPECT_NEAR(path.value().durationS(), 3.9, 1e-9);
    for (const runtime::CameraKeyframe& k : keyframes) {
        runtime::Camera expected;
        flight.apply(flight.startS() + k.timeS, expected);
        EXPECT_LT(glm::length(k.position - expected.position), 1e-6) << "t = " << k.timeS;
        EXPECT_NEAR(std::remainder(k.yaw - expected.yaw, 2.0 * 3.141592653589793), 0.0, 1e-9);
        EXPECT_NEAR(k.pitch, expected.pitch, 1e-9);
    }

    // The telemetry log: the header and one row per frame.
    std::ifstream log(csv);
    std::string header;
    std::getline(log, header);
    EXPECT_EQ(header.rfind("frame,time_s,frame_ms,", 0), 0u) << header;
    int rows = 0;
    for (std::string line; std::getline(log, line);) ++rows;
    EXPECT_EQ(rows, 40);
}

TEST_F(ViewerTool, ScreenshotShowsTerrainAndTheOverlay) {
    auto manifest = io::readManifest(kPyramid);
    ASSERT_TRUE(manifest) << manifest.error().message;
    const runtime::CameraPath flight =
        runtime::CameraPath::defaultFor(runtime::TerrainGeometry(manifest.value()), 4.0);
    const std::string flightFile = m_folder.file("flight.camera.json");
    ASSERT_TRUE(flight.save(flightFile));

    // The same settled, fixed-step flight twice: with the overlay and without it.
    const std::string common = kPyramid + " --path " + flightFile +
                               " --frames 6 --fps 2 --settle --width 640 --height 480 --json";
    const std::string withOverlay = m_folder.file("with-overlay.png");
    const std::string bare = m_folder.file("bare.png");
    const ToolRun shown = runViewer(common + " --screenshot " + withOverlay, m_folder);
    ASSERT_EQ(shown.status, 0) << describe(shown);
    const ToolRun hidden = runViewer(common + " --no-overlay --screenshot " + bare, m_folder);
    ASSERT_EQ(hidden.status, 0) << describe(hidden);

    const nlohmann::json shownSummary = summaryOf(shown);
    EXPECT_EQ(shownSummary["screenshots"], nlohmann::json::array({withOverlay}));
    EXPECT_EQ(shownSummary["gl_errors"], 0);
    const nlohmann::json& windows = shownSummary["overlay"]["windows"];
    ASSERT_EQ(windows.size(), 1u) << shownSummary["overlay"].dump();
    const nlohmann::json& w = windows[0];
    const Rect overlay{static_cast<int>(w["x"].get<double>()),
                       static_cast<int>(w["y"].get<double>()),
                       static_cast<int>(w["x"].get<double>() + w["width"].get<double>()),
                       static_cast<int>(w["y"].get<double>() + w["height"].get<double>())};
    EXPECT_GT(overlay.x1 - overlay.x0, 200);
    EXPECT_GT(overlay.y1 - overlay.y0, 150);
    EXPECT_LT(overlay.x1, 480) << "the overlay must leave room to see the terrain";
    const nlohmann::json hiddenSummary = summaryOf(hidden);
    EXPECT_EQ(hiddenSummary["overlay"]["visible"], false);
    EXPECT_TRUE(hiddenSummary["overlay"]["windows"].empty());

    const Image a = readPng(withOverlay);
    const Image b = readPng(bare);
    ASSERT_EQ(a.width, 640);
    ASSERT_EQ(a.height, 480);
    ASSERT_EQ(b.width, a.width);
    ASSERT_EQ(b.height, a.height);
    ASSERT_GE(a.channels, 3);

    double outside = 0, terrain = 0, outsideSame = 0, inside = 0, insideChanged = 0;
    double insideDifference = 0.0;
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            const int d = difference(a.at(x, y), b.at(x, y));
            if (overlay.contains(x, y)) {
                ++inside;
                insideDifference += d;
                if (d > 24) ++insideChanged;
            } else {
                ++outside;
                if (!isSky(a.at(x, y))) ++terrain;
                if (d <= 3) ++outsideSame;
            }
        }
    }
    // Terrain, not the clear colour, in much of the view the overlay leaves free.
    EXPECT_GT(terrain / outside, 0.25) << terrain << " of " << outside;
    // The overlay changed its rectangle: a dark panel with text over the terrain...
    EXPECT_GT(insideChanged / inside, 0.5) << insideChanged << " of " << inside;
    EXPECT_GT(insideDifference / inside, 60.0);
    // ... and nothing else: outside it the two settled renders agree.
    EXPECT_GT(outsideSame / outside, 0.98) << outsideSame << " of " << outside;
}

// A small globe pyramid: 100 to 700 m hills, 17 km apart, 1.1 km samples (lat 48.8–50° N,
// lon 10–12° E).
float globeHills(double lat, double lon) {
    return static_cast<float>(400.0 + 300.0 * std::sin(lat * 40.0) * std::cos(lon * 30.0));
}

std::string buildGlobeHills(const test::TempFolder& folder) {
    test::GeographicFunctionDem source(10.0, 50.0, 200, 120, 0.01, 0.01, globeHills);
    const std::string pyramid = folder.file("globe.pyramid");
    io::PyramidBuildOptions options;
    options.patchSamples = 65;
    options.blockQuads = 8;
    auto built = io::buildGlobePyramid(source, pyramid, options);
    EXPECT_TRUE(built) << built.error().message;
    return pyramid;
}

// A globe pyramid opens the viewer with the globe's controls: "go to the data" at start, settled frames, the
// screenshot shows the terrain (not the black of space) around the overlay.
TEST_F(ViewerTool, GlobePyramidOpensOverTheData) {
    const std::string pyramid = buildGlobeHills(m_folder);
    const std::string screenshot = m_folder.file("globe.png");
    const ToolRun viewed = runViewer(pyramid +
                                         " --frames 8 --settle --width 480 --height 320 "
                                         "--no-overlay --json --screenshot " +
                                         screenshot,
                                     m_folder);
    ASSERT_EQ(viewed.status, 0) << describe(viewed);
    const nlohmann::json summary = summaryOf(viewed);
    EXPECT_EQ(summary["tiling"], "globe");
    EXPECT_NEAR(summary["camera"]["latitude"].get<double>(), 49.4, 1e-9);
    EXPECT_NEAR(summary["camera"]["longitude"].get<double>(), 11.0, 1e-9);
    const Image image = readPng(screenshot);
    ASSERT_EQ(image.width, 480);
    int ground = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            ground += image.at(x, y)[0] > 40 ? 1 : 0;  // not space
    EXPECT_GT(ground, image.width * image.height * 9 / 10);
}

// On a globe the viewer keeps the camera 1 m above the ground under it, not above the highest
// point of the patch there: over the bottom of a valley (about 100 m) a jump to 1 m above
// the ellipsoid, under the ground, comes up to it, and one to 300 m stays there (the hills
// of the patch reach 700 m).
TEST_F(ViewerTool, GlobeCameraStaysJustAboveTheGround) {
    const std::string pyramid = buildGlobeHills(m_folder);
    const double lat = 49.755, lon = 10.472;  // sin(lat · 40) ≈ −1, cos(lon · 30) ≈ 1
    const double ground = globeHills(lat, lon);
    ASSERT_LT(ground, 101.0);
    for (const double altitude : {1.0, 300.0}) {
        SCOPED_TRACE(altitude);
        const ToolRun viewed = runViewer(pyramid + " --goto " + std::to_string(lat) + "," +
                                             std::to_string(lon) + "," + std::to_string(altitude) +
                                             " --frames 12 --settle --width 320 --height 200 "
                                             "--no-overlay --json",
                                         m_folder);
        ASSERT_EQ(viewed.status, 0) << describe(viewed);
        const double camera = summaryOf(viewed)["camera"]["altitude_m"].get<double>();
        if (altitude == 1.0) {
            // Above the ground, by at most the rise across one 1.1 km sample (120 m here).
            EXPECT_GE(camera, ground + 1.0 - 5.0);
            EXPECT_LE(camera, ground + 1.0 + 130.0);
        } else {
            EXPECT_DOUBLE_EQ(camera, altitude);
        }
    }
}

// One viewer for both surfaces: on a globe the overlay, ε, the telemetry log, the path
// recorder and the summary are the planar viewer's, only the camera (latitude, longitude) is
// the globe's. A recorded globe path plays back through the same frames; a planar path is
// refused by what it is.
TEST_F(ViewerTool, GlobeViewerHasThePlanarViewersOverlayLogPathsAndSummary) {
    const std::string pyramid = buildGlobeHills(m_folder);
    const std::string csv = m_folder.file("globe-telemetry.csv");
    const std::string recorded = m_folder.file("globe.camera.json");
    // W held is not available headless: the flight is the wheel-free start, a fixed pose
    // recorded over 2 s of flight time (20 frames at 10 per second).
    const ToolRun viewed = runViewer(pyramid +
                                         " --frames 20 --fps 10 --width 480 --height 320 "
                                         "--goto 49.4,11.0,3000 --error-px 3 --json "
                                         "--telemetry " +
                                         csv + " --record " + recorded,
                                     m_folder);
    ASSERT_EQ(viewed.status, 0) << describe(viewed);
    const nlohmann::json summary = summaryOf(viewed);
    EXPECT_EQ(summary["tiling"], "globe");
    EXPECT_EQ(summary["error_px"], 3.0);
    EXPECT_EQ(summary["gl_errors"], 0);
    EXPECT_GT(summary["patches_drawn_last"].get<int>(), 0);
    EXPECT_EQ(summary["telemetry_csv"], nlohmann::json::array({csv}));
    EXPECT_EQ(summary["paths_recorded"], nlohmann::json::array({recorded}));
    ASSERT_EQ(summary["overlay"]["windows"].size(), 1u);
    EXPECT_GT(summary["overlay"]["windows"][0]["height"].get<double>(), 100.0);
    std::ifstream log(csv);
    int rows = -1;  // the header
    for (std::string line; std::getline(log, line);) ++rows;
    EXPECT_EQ(rows, 20);

    auto path = runtime::FlightPath::load(recorded);
    ASSERT_TRUE(path) << path.error().message;
    ASSERT_NE(path.value().globe(), nullptr) << "a globe pyramid records a globe path";
    EXPECT_NEAR(path.value().durationS(), 1.9, 1e-9);
    const runtime::GlobePose end = path.value().globe()->poseAt(path.value().endS());
    EXPECT_NEAR(end.where.latitudeDeg, 49.4, 1e-9);
    EXPECT_NEAR(end.where.longitudeDeg, 11.0, 1e-9);

    const ToolRun played = runViewer(pyramid + " --path " + recorded +
                                         " --frames 5 --fps 10 --width 320 --height 200 "
                                         "--no-overlay --json",
                                     m_folder);
    ASSERT_EQ(played.status, 0) << describe(played);
    EXPECT_NEAR(summaryOf(played)["camera"]["latitude"].get<double>(), 49.4, 1e-6);
    EXPECT_NEAR(summaryOf(played)["path_time_s"].get<double>(), 0.4, 1e-9);

    const runtime::CameraPath planar = runtime::CameraPath::defaultFor(
        runtime::TerrainGeometry(io::readManifest(kPyramid).value()), 4.0);
    const std::string planarFile = m_folder.file("planar.camera.json");
    ASSERT_TRUE(planar.save(planarFile));
    const ToolRun refused = run(kViewer + " " + pyramid + " --path " + planarFile, m_folder);
    EXPECT_EQ(refused.status, 1) << describe(refused);
    EXPECT_NE(refused.err.find("a planar camera path"), std::string::npos) << refused.err;
}

TEST_F(ViewerTool, FliesTheOtherStreamingLodMethodsAndRefusesTheInCoreOnes) {
    for (const std::string method : {"chunked-lod", "uniform"}) {
        const ToolRun r = runViewer(kPyramid + " --method " + method +
                                        " --frames 6 --settle --width 240 --height 160 --json",
                                    m_folder);
        ASSERT_EQ(r.status, 0) << method << ": " << describe(r);
        const nlohmann::json summary = summaryOf(r);
        EXPECT_EQ(summary["method"], method);
        EXPECT_EQ(summary["gl_errors"], 0);
        EXPECT_GT(summary["patches_drawn_last"].get<int>(), 0) << method;
    }
    for (const std::string inCore : {"rtin", "lee2011", "ripolles"}) {
        const ToolRun refused =
            run("env -u DISPLAY " + kViewer + " " + kPyramid + " --method " + inCore, m_folder);
        EXPECT_EQ(refused.status, 1) << describe(refused);
        EXPECT_NE(refused.err.find(inCore + " streams nothing"), std::string::npos) << refused.err;
    }
}

TEST_F(ViewerTool, MissingPyramidIsAClearError) {
    // No display either: the pyramid is checked before any window opens.
    const ToolRun r =
        run("env -u DISPLAY " + kViewer + " " + m_folder.file("no-such.pyramid"), m_folder);
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.err.find("no-such.pyramid"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("terrain-view: "), std::string::npos) << r.err;
}

TEST_F(ViewerTool, InvalidPyramidIsAClearError) {
    const fs::path broken = m_folder.path() / "broken.pyramid";
    fs::create_directories(broken);
    std::ofstream(broken / "manifest.json")
        << "{\"format\": \"terrain-pyramid\", \"formatVersion\": 8";
    const ToolRun r = run(kViewer + " " + broken.string(), m_folder);
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.err.find("manifest.json"), std::string::npos) << r.err;
}

// A root patch that cannot be read leaves nothing to draw: the viewer says so on stderr and
// on screen, with the shard's name, and exits 1 instead of showing an empty picture (with
// --settle it does not wait the whole settle timeout for a root that will never come).
TEST_F(ViewerTool, UnreadableRootIsAClearError) {
    const fs::path damaged = m_folder.path() / "damaged-root.pyramid";
    fs::copy(kPyramid, damaged, fs::copy_options::recursive);
    std::ofstream(damaged / "L0" / "0" / "0.exr", std::ios::trunc) << "not an OpenEXR shard\n";
    const ToolRun r =
        runViewer(damaged.string() + " --frames 3 --settle --width 160 --height 120", m_folder);
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.err.find("0.exr"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("nothing to draw"), std::string::npos) << r.err;
}

TEST_F(ViewerTool, MissingPathFileIsAClearError) {
    const ToolRun r =
        run(kViewer + " " + kPyramid + " --path " + m_folder.file("nope.camera.json"), m_folder);
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.err.find("nope.camera.json"), std::string::npos) << r.err;
}

TEST_F(ViewerTool, UnwritableOutputFolderIsAClearError) {
    const std::string target = m_folder.file("no-such-folder/shot.png");
    const ToolRun r = run(kViewer + " " + kPyramid + " --screenshot " + target, m_folder);
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.err.find("shot.png"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
}

TEST_F(ViewerTool, NoDisplayIsAClearError) {
    const ToolRun r =
        run("env -u DISPLAY -u WAYLAND_DISPLAY " + kViewer + " " + kPyramid, m_folder);
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.err.find("DISPLAY"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("xvfb-run"), std::string::npos) << r.err;
}

TEST_F(ViewerTool, NoOpenGl45IsAClearError) {
    // Mesa reports at most OpenGL 4.1 here, so no 4.5 core context can be made.
    const ToolRun r = runViewer(kPyramid + " --frames 1", m_folder,
                                "MESA_GL_VERSION_OVERRIDE=4.1 MESA_GLSL_VERSION_OVERRIDE=410");
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.err.find("OpenGL 4.5"), std::string::npos) << r.err;
}

TEST_F(ViewerTool, HelpListsOptionsAndKeys) {
    const ToolRun r = run(kViewer + " --help", m_folder);
    EXPECT_EQ(r.status, 0) << describe(r);
    for (const char* expected : {"--path", "--record", "--screenshot", "--telemetry", "--frames",
                                 "--exit-after", "--no-vsync", "--json", "F12", "freeze"}) {
        EXPECT_NE(r.out.find(expected), std::string::npos) << expected;
    }
}

}  // namespace
}  // namespace terrain

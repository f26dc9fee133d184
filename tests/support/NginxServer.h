// NginxServer: a real static web server (Debian's nginx, installed by scripts/setup.sh) serving
// one folder on 127.0.0.1 for a test, the way a user hosts a pyramid (issue 49). Started on a
// free port in the foreground (no daemon, no master process, every path in a temporary
// folder, so no root is needed) and stopped when the object goes. ready() says whether it
// answers; the test skips with the reason when nginx is not installed, and
// TERRAIN_REQUIRE_SHARED_DATA (set by CI) turns that skip into a failure.
#pragma once

#include "SharedData.h"
#include "TempFolder.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace terrain::test {

class NginxServer {
public:
    static constexpr const char* kNginx = "/usr/sbin/nginx";

    explicit NginxServer(const std::filesystem::path& root) {
        if (!std::filesystem::exists(kNginx)) {
            m_problem = std::string(kNginx) + " is not installed (scripts/setup.sh installs it)";
            return;
        }
        for (int attempt = 0; attempt < 5 && m_pid <= 0; ++attempt) start(root);
    }
    ~NginxServer() { stop(); }
    NginxServer(const NginxServer&) = delete;
    NginxServer& operator=(const NginxServer&) = delete;

    bool ready() const { return m_pid > 0; }
    /// Why it is not ready.
    const std::string& problem() const { return m_problem; }
    /// "http://127.0.0.1:<port>/" + path.
    std::string url(const std::string& path) const {
        return "http://127.0.0.1:" + std::to_string(m_port) + "/" + path;
    }
    int port() const { return m_port; }
    /// Requests served so far, from the access log (one line a request). nginx writes a
    /// request's line just after sending its last byte, so a client that has its answer may
    /// read the log before the line is there; one request to a location that is not logged,
    /// answered by the same single worker, comes after every earlier line is written.
    std::vector<std::string> accessLog() const {
        awaitEarlierRequestsLogged();
        std::vector<std::string> lines;
        std::ifstream in(m_folder.path() / "access.log");
        for (std::string line; std::getline(in, line);) lines.push_back(line);
        return lines;
    }

    void stop() {
        if (m_pid <= 0) return;
        ::kill(m_pid, SIGTERM);
        int status = 0;
        ::waitpid(m_pid, &status, 0);
        m_pid = -1;
    }

private:
    // 127.0.0.1:port.
    static sockaddr_in loopback(int port) {
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        address.sin_port = htons(static_cast<std::uint16_t>(port));
        return address;
    }

    // A socket connected to 127.0.0.1:port, or -1 when nothing answers there.
    static int connectTo(int port) {
        const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
        const sockaddr_in address = loopback(port);
        if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0)
            return fd;
        ::close(fd);
        return -1;
    }

    // A port nothing listens on now (the kernel's pick for port 0).
    static int freePort() {
        const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in address = loopback(0);
        socklen_t length = sizeof(address);
        int port = 0;
        if (::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0 &&
            ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0)
            port = ntohs(address.sin_port);
        ::close(fd);
        return port;
    }

    // The worker handles one event at a time and logs a request in the same step that sends
    // its last byte: once it has answered this request, every earlier answer is logged.
    void awaitEarlierRequestsLogged() const {
        const int fd = connectTo(m_port);
        if (fd < 0) return;
        const std::string request = "GET /.log-barrier HTTP/1.0\r\n\r\n";
        if (::send(fd, request.data(), request.size(), MSG_NOSIGNAL) ==
            static_cast<ssize_t>(request.size())) {
            char buffer[512];
            while (::recv(fd, buffer, sizeof(buffer), 0) > 0) {
            }
        }
        ::close(fd);
    }

    static bool answers(int port) {
        const int fd = connectTo(port);
        if (fd >= 0) ::close(fd);
        return fd >= 0;
    }

    void start(const std::filesystem::path& root) {
        m_port = freePort();
        const std::string dir = m_folder.path().string();
        {
            std::ofstream conf(m_folder.path() / "nginx.conf");
            conf << "worker_processes 1;\ndaemon off;\nmaster_process off;\n"
                 << "pid " << dir << "/nginx.pid;\nerror_log " << dir << "/error.log;\n"
                 << "events { worker_connections 64; }\nhttp {\n"
                 << "  access_log " << dir << "/access.log;\n"
                 << "  client_body_temp_path " << dir << "/body;\n"
                 << "  proxy_temp_path " << dir << "/proxy;\n"
                 << "  fastcgi_temp_path " << dir << "/fastcgi;\n"
                 << "  uwsgi_temp_path " << dir << "/uwsgi;\n"
                 << "  scgi_temp_path " << dir << "/scgi;\n"
                 << "  server { listen 127.0.0.1:" << m_port << "; root " << root.string()
                 << ";\n    location = /.log-barrier { access_log off; return 204; }\n  }\n}\n";
        }
        const std::string conf = dir + "/nginx.conf", errorLog = dir + "/error.log";
        const char* argv[] = {kNginx,       "-p", dir.c_str(),      "-c",
                              conf.c_str(), "-e", errorLog.c_str(), nullptr};
        pid_t pid = -1;
        if (::posix_spawn(&pid, kNginx, nullptr, nullptr, const_cast<char**>(argv), environ) != 0) {
            m_problem = "cannot start nginx";
            return;
        }
        // Wait for the outcome: it answers, or it exited (the port was taken meanwhile).
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while (std::chrono::steady_clock::now() < deadline) {
            int status = 0;
            if (::waitpid(pid, &status, WNOHANG) == pid) {
                m_problem = "nginx exited at start; see its error log";
                return;
            }
            if (answers(m_port)) {
                m_pid = pid;
                return;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        ::kill(pid, SIGKILL);
        ::waitpid(pid, nullptr, 0);
        m_problem = "nginx did not answer within 20 s";
    }

    TempFolder m_folder;
    int m_port = 0;
    pid_t m_pid = -1;
    std::string m_problem;
};

}  // namespace terrain::test

/// In a fixture's SetUp: skips the test, with the reason, when `server` (an NginxServer) does
/// not answer, or fails it under TERRAIN_REQUIRE_SHARED_DATA=1, where CI must run it.
#define TERRAIN_NGINX_OR_SKIP(server)                                            \
    if (!(server).ready()) {                                                     \
        if (::terrain::test::sharedDataRequired()) FAIL() << (server).problem(); \
        GTEST_SKIP() << (server).problem();                                      \
    }

// XvfbServer: a private virtual X server for one test process, started directly rather than
// through xvfb-run. Xvfb picks a free display number itself and writes it to a pipe
// (-displayfd), so tests running in parallel never race for a number, and a test checks its
// program's own exit status, never a wrapper's (xvfb-run exits 5 now and then after a clean
// run: "problem while cleaning up temporary directory"). The server is stopped and reaped
// when the object goes.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

namespace terrain::test {

class XvfbServer {
public:
    /// Starts `xvfb` (the Xvfb program's path); display() is empty and error() says why
    /// when it could not be started within `timeoutMs`.
    explicit XvfbServer(const std::string& xvfb, int timeoutMs = 30000) {
        int fds[2] = {-1, -1};
        if (::pipe(fds) != 0) {
            m_error = std::string("pipe: ") + std::strerror(errno);
            return;
        }
        // Between fork and exec only async-signal-safe calls: nothing allocates there.
        const std::string fd = std::to_string(fds[1]);
        m_pid = ::fork();
        if (m_pid == 0) {
            ::close(fds[0]);
            const int quiet = ::open("/dev/null", O_WRONLY);
            if (quiet >= 0) ::dup2(quiet, STDERR_FILENO);
            ::execl(xvfb.c_str(), xvfb.c_str(), "-displayfd", fd.c_str(), "-screen", "0",
                    "1280x1024x24", "-nolisten", "tcp", static_cast<char*>(nullptr));
            ::_exit(127);
        }
        ::close(fds[1]);
        if (m_pid < 0) {
            m_error = std::string("fork: ") + std::strerror(errno);
            ::close(fds[0]);
            return;
        }
        // The display number, then a newline, once the server accepts connections.
        std::string number;
        pollfd ready{fds[0], POLLIN, 0};
        while (::poll(&ready, 1, timeoutMs) > 0) {
            char c = 0;
            if (::read(fds[0], &c, 1) != 1 || c == '\n') break;
            number.push_back(c);
        }
        ::close(fds[0]);
        if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos) {
            m_error = xvfb + " did not report a display within " + std::to_string(timeoutMs) +
                      " ms (is the Debian package xvfb installed?)";
            return;
        }
        m_display = ":" + number;
    }
    ~XvfbServer() {
        if (m_pid <= 0) return;
        ::kill(m_pid, SIGTERM);
        int status = 0;
        ::waitpid(m_pid, &status, 0);
    }
    XvfbServer(const XvfbServer&) = delete;
    XvfbServer& operator=(const XvfbServer&) = delete;

    const std::string& display() const { return m_display; }  ///< ":N", or empty
    const std::string& error() const { return m_error; }

private:
    pid_t m_pid = -1;
    std::string m_display;
    std::string m_error;
};

}  // namespace terrain::test

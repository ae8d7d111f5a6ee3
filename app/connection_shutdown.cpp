// shut_connections_down: the process's own descriptors, from /proc/self/fd, that are TCP
// connections accepted on a port, shut down.
#include "app/connection_shutdown.h"

#include <dirent.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>

#include <cstdlib>

namespace wsd::app {

namespace {

// The local port of a connected TCP socket `fd`, or -1 for anything else (a listening socket, a
// file, a closed descriptor).
int connection_port(int fd) {
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISSOCK(st.st_mode)) return -1;
    sockaddr_storage local{}, peer{};
    socklen_t size = sizeof local;
    if (::getsockname(fd, reinterpret_cast<sockaddr*>(&local), &size) != 0) return -1;
    size = sizeof peer;
    if (::getpeername(fd, reinterpret_cast<sockaddr*>(&peer), &size) != 0) return -1;
    if (local.ss_family == AF_INET) return ntohs(reinterpret_cast<const sockaddr_in&>(local).sin_port);
    if (local.ss_family == AF_INET6) return ntohs(reinterpret_cast<const sockaddr_in6&>(local).sin6_port);
    return -1;
}

}  // namespace

void shut_connections_down(int port) {
    DIR* dir = ::opendir("/proc/self/fd");
    if (!dir) return;
    const int own = ::dirfd(dir);
    while (const dirent* entry = ::readdir(dir)) {
        char* end = nullptr;
        const long fd = std::strtol(entry->d_name, &end, 10);
        if (end == entry->d_name || *end != '\0' || fd == own) continue;
        if (connection_port(int(fd)) == port) ::shutdown(int(fd), SHUT_RDWR);
    }
    ::closedir(dir);
}

}  // namespace wsd::app

// Ending a server's open connections from outside the server: cpp-httplib ends a connection only
// between requests, so a slow or idle client could hold a server's stop up. Linux only (it reads
// /proc/self/fd, as the preview's inotify watching is Linux only too).
#pragma once

namespace wsd::app {

// Shuts down every connection this process accepted on `port`: a thread reading or writing one
// returns at once and closes it.
void shut_connections_down(int port);

}  // namespace wsd::app

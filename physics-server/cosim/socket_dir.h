// The private directory of a run's listening socket, in the system's
// temporary directory: chainsim-sock-<server pid>-XXXXXX, 0700. The server
// removes it when it ends; a server killed outright (SIGKILL, SIGABRT) cannot,
// so each new one first removes those whose server is gone.
#pragma once

#include <string>

namespace chainsim {

// creates a fresh socket directory in tmp_dir (default: the system's); throws
// std::runtime_error naming the place
std::string make_socket_dir(const std::string& tmp_dir = "");

// removes the socket directories in tmp_dir (default: the system's) that are
// ours (same user) and whose server process no longer exists; returns how
// many. A directory whose pid is alive (even reused by another process) is
// left alone. Also removes those of the old naming (below).
int remove_stale_socket_dirs(const std::string& tmp_dir = "");

// The old naming, chainsim-XXXXXX, says no pid. Such a directory is removed
// only when it is ours, 0700, holds nothing but a socket named chainsim.sock
// (or nothing), has not changed for min_age_s, and no socket of this system
// (/proc/net/unix) is bound to that name: a live server of the old naming
// keeps its socket bound. Returns how many were removed; none when
// /proc/net/unix cannot be read.
int remove_stale_old_socket_dirs(const std::string& tmp_dir = "", double min_age_s = 60.0);

}  // namespace chainsim

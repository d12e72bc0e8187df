// The viewer's HTTP server (cpp-httplib 0.11) made to survive hostile clients on the same
// machine: a whole-request deadline instead of a timeout per byte (a client trickling its
// headers a byte a second is dropped), a cap on the connections of one client address, enough
// workers that the other clients are served meanwhile, and byte ranges checked against the
// file's size (cpp-httplib 0.11 answers a range past the end with a 206 and a wrapped length).
#pragma once

#include <chrono>
#include <cstddef>
#include <list>
#include <mutex>
#include <string>

// Last: through <resolv.h> it defines the macro `_res`, which breaks Eigen included after it.
#include <httplib.h>

namespace linx::cli {

struct ViewServerLimits {
  /// From the connection's accept (or the end of the previous answer on a kept-alive one) to the
  /// last byte of the request's headers.
  std::chrono::milliseconds request_deadline{4000};
  /// From the request's start to the last byte of its answer.
  std::chrono::milliseconds answer_deadline{60000};
  /// Any one read or write waits at most this long.
  std::chrono::milliseconds io_timeout{2000};
  /// How long a kept-alive connection waits for its next request, and how many it may carry.
  std::chrono::milliseconds keep_alive{1000};
  std::size_t keep_alive_requests = 5;
  /// Connections waiting for a request (not yet answering) from one client address, and in all:
  /// a new connection past either ends the one of them that has waited longest. A request comes
  /// in one packet, so it is the slow and idle connections that are ended.
  std::size_t waiting_per_client = 16;
  std::size_t waiting = 32;
  /// Connections served at once (more wait in the queue, and are dropped unread once their
  /// request deadline has passed there).
  std::size_t workers = 64;
};

class ViewServer : public httplib::Server {
 public:
  explicit ViewServer(ViewServerLimits limits = {});

  /// After a bind: lets `backlog` connections wait for their accept (cpp-httplib listens with 5,
  /// so that a burst of connections had the later ones wait a second each for the SYN again).
  void widenBacklog(int backlog = 1024);

  struct Connection {
    int sock;
    std::string client;                           // its address
    std::chrono::steady_clock::time_point since;  // waiting since
    bool waiting = true;                          // for a request (false: answering one)
    bool ended = false;                           // shut down to make room
  };

 private:
  bool process_and_close_socket(socket_t sock) override;
  // Registers a connection that waits for its first request, ending the longest-waiting one
  // of its client (or of all) when there is no room.
  std::list<Connection>::iterator enter(int sock, std::string client);
  void leave(std::list<Connection>::iterator it);
  void setWaiting(std::list<Connection>::iterator it, bool waiting);
  void makeRoom(const std::string& client);

  ViewServerLimits limits_;
  std::mutex mutex_;
  std::list<Connection> connections_;  // each removed before its socket is closed
};

/// Checks the request's byte ranges against a file of `size` bytes. Ranges that start past the
/// end (or ask for an empty suffix) are dropped and the others clipped to the file, in place,
/// so that cpp-httplib sends exactly them; when none is left, or more than `most` were asked
/// for, `res` becomes a 416 (Range Not Satisfiable) with `Content-Range: bytes */SIZE` and false
/// is returned. (cpp-httplib refuses a malformed or overflowing Range with a 416 itself.)
bool fitRanges(const httplib::Request& req, std::size_t size, std::size_t most,
               httplib::Response& res);

/// Drops the request's byte ranges, for an answer that is not the file asked for (an error).
void dropRanges(const httplib::Request& req);

}  // namespace linx::cli

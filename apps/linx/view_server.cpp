#include "view_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <functional>
#include <limits>
#include <list>
#include <memory>
#include <utility>
#include <vector>

namespace linx::cli {

namespace {

using Clock = std::chrono::steady_clock;

// When the connection a worker is about to serve was accepted (set by StampedPool).
thread_local Clock::time_point accepted_at;

// cpp-httplib's thread pool, each job stamped with the time its connection was accepted, so that
// a connection that waited in the queue past its deadline is dropped unread.
class StampedPool : public httplib::TaskQueue {
 public:
  explicit StampedPool(std::size_t workers) : pool_(workers) {}
  void enqueue(std::function<void()> fn) override {
    pool_.enqueue([fn = std::move(fn), at = Clock::now()] {
      accepted_at = at;
      fn();
    });
  }
  void shutdown() override { pool_.shutdown(); }

 private:
  httplib::ThreadPool pool_;
};

// Waits until `sock` is ready for `events`, at most until `until`: false on a timeout or error.
bool waitFor(int sock, short events, Clock::time_point until) {
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now());
    if (left.count() <= 0) return false;
    pollfd p{sock, events, 0};
    const int n = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 1 << 30)));
    if (n < 0 && errno == EINTR) continue;
    return n > 0 && (p.revents & (events | POLLHUP | POLLERR)) != 0;
  }
}

std::string addressOf(const sockaddr_storage& a, int& port) {
  char text[INET6_ADDRSTRLEN] = "";
  port = 0;
  if (a.ss_family == AF_INET) {
    const auto* v4 = reinterpret_cast<const sockaddr_in*>(&a);
    ::inet_ntop(AF_INET, &v4->sin_addr, text, sizeof text);
    port = ntohs(v4->sin_port);
  } else if (a.ss_family == AF_INET6) {
    const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&a);
    ::inet_ntop(AF_INET6, &v6->sin6_addr, text, sizeof text);
    port = ntohs(v6->sin6_port);
  }
  return text;
}

std::string peerOf(int sock, int& port) {
  sockaddr_storage a{};
  socklen_t length = sizeof a;
  if (::getpeername(sock, reinterpret_cast<sockaddr*>(&a), &length) != 0) return {};
  return addressOf(a, port);
}

// A connection whose reads end at a deadline for the whole request (not a timeout per byte) and
// whose writes end at a deadline for the whole answer.
class DeadlineStream : public httplib::Stream {
 public:
  // `answering` is called at the first write of each request's answer.
  DeadlineStream(int sock, const ViewServerLimits& limits, std::function<void()> answering)
      : sock_(sock), limits_(limits), answering_(std::move(answering)) {}

  // A new request starts at `start`: its headers are due by the request deadline.
  void begin(Clock::time_point start) {
    read_until_ = start + limits_.request_deadline;
    write_until_ = start + limits_.answer_deadline;
    answered_ = false;
  }

  bool is_readable() const override {
    return offset_ < size_ || waitFor(sock_, POLLIN, readLimit());
  }
  bool is_writable() const override { return waitFor(sock_, POLLOUT, writeLimit()); }

  ssize_t read(char* ptr, std::size_t size) override {
    if (offset_ == size_) {
      if (!waitFor(sock_, POLLIN, readLimit())) return -1;
      ssize_t n;
      do n = ::recv(sock_, buffer_.data(), buffer_.size(), 0);
      while (n < 0 && errno == EINTR);
      if (n <= 0) return n;
      offset_ = 0;
      size_ = static_cast<std::size_t>(n);
    }
    const std::size_t n = std::min(size, size_ - offset_);
    std::copy_n(buffer_.data() + offset_, n, ptr);
    offset_ += n;
    return static_cast<ssize_t>(n);
  }

  ssize_t write(const char* ptr, std::size_t size) override {
    if (!answered_) {
      answered_ = true;
      answering_();
    }
    if (!waitFor(sock_, POLLOUT, writeLimit())) return -1;
    ssize_t n;
    do n = ::send(sock_, ptr, size, MSG_NOSIGNAL | MSG_DONTWAIT);
    while (n < 0 && errno == EINTR);
    return n;
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = peerOf(sock_, port);
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    sockaddr_storage a{};
    socklen_t length = sizeof a;
    ip.clear();
    port = 0;
    if (::getsockname(sock_, reinterpret_cast<sockaddr*>(&a), &length) == 0)
      ip = addressOf(a, port);
  }
  socket_t socket() const override { return sock_; }

  bool buffered() const { return offset_ < size_; }

 private:
  Clock::time_point readLimit() const {
    return std::min(read_until_, Clock::now() + limits_.io_timeout);
  }
  Clock::time_point writeLimit() const {
    return std::min(write_until_, Clock::now() + limits_.io_timeout);
  }

  int sock_;
  const ViewServerLimits& limits_;
  std::function<void()> answering_;
  bool answered_ = false;
  Clock::time_point read_until_{}, write_until_{};
  std::vector<char> buffer_ = std::vector<char>(4096);
  std::size_t offset_ = 0, size_ = 0;
};

}  // namespace

ViewServer::ViewServer(ViewServerLimits limits) : limits_(limits) {
  new_task_queue = [workers = limits_.workers] { return new StampedPool(workers); };
  // What cpp-httplib tells clients in its Keep-Alive header (the loop here enforces them).
  set_keep_alive_max_count(limits_.keep_alive_requests);
  set_keep_alive_timeout(
      std::chrono::duration_cast<std::chrono::seconds>(limits_.keep_alive).count());
  // The viewer takes no request bodies: one is read at most this far (and answered 413 beyond).
  set_payload_max_length(64 * 1024);
}

void ViewServer::widenBacklog(int backlog) {
  if (svr_sock_ != INVALID_SOCKET) ::listen(svr_sock_, backlog);
}

void ViewServer::makeRoom(const std::string& client) {
  std::size_t mine = 0, all = 0;
  auto oldest_mine = connections_.end(), oldest = connections_.end();
  for (auto it = connections_.begin(); it != connections_.end(); ++it) {
    if (!it->waiting || it->ended) continue;
    ++all;
    if (oldest == connections_.end() || it->since < oldest->since) oldest = it;
    if (it->client != client) continue;
    ++mine;
    if (oldest_mine == connections_.end() || it->since < oldest_mine->since) oldest_mine = it;
  }
  const auto end = [](Connection& c) {
    ::shutdown(c.sock, SHUT_RDWR);  // its worker's next read fails; the worker closes it
    c.ended = true;
  };
  if (mine >= limits_.waiting_per_client)
    end(*oldest_mine);
  else if (all >= limits_.waiting)
    end(*oldest);
}

std::list<ViewServer::Connection>::iterator ViewServer::enter(int sock, std::string client) {
  const std::lock_guard lock(mutex_);
  makeRoom(client);
  // Waiting since now, not since its accept: one that sat in the queue is read at once, and is
  // not the one to end.
  return connections_.insert(connections_.end(), Connection{sock, std::move(client), Clock::now()});
}

void ViewServer::setWaiting(std::list<Connection>::iterator it, bool waiting) {
  const std::lock_guard lock(mutex_);
  it->waiting = waiting;
  it->since = Clock::now();
}

void ViewServer::leave(std::list<Connection>::iterator it) {
  const std::lock_guard lock(mutex_);
  connections_.erase(it);
}

bool ViewServer::process_and_close_socket(socket_t sock) {
  const auto close = [sock] {
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
  };
  // Waited in the queue past its deadline: the client has had its time.
  Clock::time_point start = accepted_at;
  if (Clock::now() - start >= limits_.request_deadline) {
    close();
    return false;
  }
  int port = 0;
  const auto connection = enter(sock, peerOf(sock, port));
  DeadlineStream stream(sock, limits_, [&] { setWaiting(connection, false); });
  bool ok = false;
  for (std::size_t count = limits_.keep_alive_requests; count > 0; --count) {
    if (svr_sock_ == INVALID_SOCKET) break;  // stopping
    // The first request's headers are due by the deadline from the accept; a kept-alive
    // connection waits a little for its next request, whose deadline starts when it comes.
    if (count < limits_.keep_alive_requests) {
      setWaiting(connection, true);
      if (!stream.buffered() && !waitFor(sock, POLLIN, Clock::now() + limits_.keep_alive)) break;
      start = Clock::now();
    }
    stream.begin(start);
    bool closed = false;
    ok = process_request(stream, count == 1, closed, nullptr);
    if (!ok || closed) break;
  }
  leave(connection);  // before the close: no one shuts down a descriptor reused by then
  close();
  return ok;
}

namespace {

// The request is the server's own (not const) object: its ranges are rewritten in place, as
// cpp-httplib serves req.ranges after the handler returns.
httplib::Ranges& rangesOf(const httplib::Request& req) {
  return const_cast<httplib::Request&>(req).ranges;
}

}  // namespace

void dropRanges(const httplib::Request& req) {
  rangesOf(req).clear();
}

bool fitRanges(const httplib::Request& req, std::size_t size, std::size_t most,
               httplib::Response& res) {
  if (req.ranges.empty()) return true;
  auto& ranges = rangesOf(req);
  if (ranges.size() > most) {
    ranges.clear();
    res.status = 416;
    res.set_header("Content-Range", "bytes */" + std::to_string(size));
    res.set_content("linx view: at most " + std::to_string(most) + " ranges a request\n",
                    "text/plain");
    return false;
  }
  const auto n = static_cast<ssize_t>(
      std::min<std::size_t>(size, static_cast<std::size_t>(std::numeric_limits<ssize_t>::max())));
  httplib::Ranges fitted;
  for (auto [first, last] : ranges) {
    if (first < 0) {  // a suffix: the last `last` bytes
      if (last <= 0 || n == 0) continue;
      first = std::max<ssize_t>(0, n - last);
      last = n - 1;
    } else {
      if (first >= n) continue;
      last = last < 0 ? n - 1 : std::min(last, n - 1);
    }
    fitted.emplace_back(first, last);
  }
  ranges = fitted;
  if (!ranges.empty()) return true;
  res.status = 416;
  res.set_header("Content-Range", "bytes */" + std::to_string(size));
  res.set_content("linx view: no byte of the range is in the file\n", "text/plain");
  return false;
}

}  // namespace linx::cli

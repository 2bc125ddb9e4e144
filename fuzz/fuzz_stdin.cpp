// Standard input ("-", `cmr analyze -`): the bytes after the first come in
// through file descriptor 0 itself, made each time the way a shell makes it,
// and are read by read_input_file (spline/spline_json.cpp), the one reader
// of "-" and of FIFOs; then, as `cmr analyze -` does, read_spline_document,
// spline_file_dimension and the planar or space reader.
//
// The first byte m chooses what descriptor 0 is (m % 8) and how it is fed
// (m >> 3):
//   0  a pipe, written in chunks of 2^(4 + (m>>3) % 13) bytes
//      (`cmr knots F insert U | cmr analyze -`); the writer's end is closed
//      after the last byte, so no bytes is an empty, closed pipe
//   1  the same pipe with O_NONBLOCK on its reading end, written by a thread
//      (the reader's poll path: a standard input left non-blocking)
//   2  a regular file (memfd) positioned (m>>3) bytes in
//      (`cmr analyze - < F`, and `(head -c N; cmr analyze -) < F`)
//   3  a stream socket (socketpair), written and closed
//   4  /dev/null (`cmr analyze - < /dev/null`)
//   5  descriptor 0 closed (fstat: EBADF)
//   6  closed at start, as cmr's main leaves it (`cmr analyze - <&-`: /dev/null
//      on 0 and note_stdin_closed)
//   7  the pipe of 0, read by the path /dev/stdin (the named-FIFO path: opened
//      again, non-blocking)
// The 64 MiB input limit is not fuzzed (-max_len is 64 KiB): one such input
// took 2 to 3 minutes at nice 19 on the loaded 2-core VM, past -timeout; a
// pipe past it is PipesCli's `head -c 67108865 /dev/zero | cmr analyze -`.
//
// Checked: what is read is exactly what was written; empty or closed is the
// documented one line ("stdin: empty (...)", "stdin: closed (...)"); a
// second read of "-" gives the same text; every InputError is one line
// naming the input.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <thread>

#include <nlohmann/json.hpp>

#include "spline/errors.hpp"
#include "spline/space.hpp"
#include "spline/spline_json.hpp"

namespace {

int g_saved_stdin = -1;  // the fuzzer's own descriptor 0, put back after each input

[[noreturn]] void fail() { __builtin_trap(); }

/// Writes in chunks; what is left when the descriptor would block (it is
/// non-blocking) or is closed at the other end (EPIPE; SIGPIPE is ignored).
std::string_view write_all(int fd, std::string_view bytes, std::size_t chunk) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), std::min(chunk, bytes.size()));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return bytes;
}

bool starts_with(const std::string& s, std::string_view prefix) { return s.compare(0, prefix.size(), prefix) == 0; }

/// An InputError's message: one line, naming the input.
void check_message(const std::string& what, std::string_view name) {
  if (what.find('\n') != std::string::npos || !starts_with(what, std::string(name) + ": ")) fail();
}

/// What `cmr analyze -` does with the text once it is read ("-" is read
/// again: the kept text).
void read_as_cmr_analyze_does() {
  try {
    const nlohmann::json doc = cmr::read_spline_document(cmr::kStdinPath);
    if (cmr::spline_file_dimension(cmr::kStdinPath, doc) == 3) (void)cmr::read_space_spline_file(cmr::kStdinPath);
    else (void)cmr::spline_from_document(doc, cmr::kStdinPath);
  } catch (const cmr::InputError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::signal(SIGPIPE, SIG_IGN);  // as cmr's main
  g_saved_stdin = ::fcntl(0, F_DUPFD_CLOEXEC, 3);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const unsigned m = data[0];
  const unsigned kind = m % 8;
  const std::string payload(reinterpret_cast<const char*>(data + 1), size - 1);
  cmr::forget_stdin();

  std::string expected = payload;
  std::thread writer;
  int other = -1;  // the writing end of the pipe or socket
  bool ok = true;
  switch (kind) {
    case 0:
    case 1:
    case 7: {
      int p[2];
      if (::pipe2(p, O_CLOEXEC) != 0) return 0;
      if (kind == 1) ::fcntl(p[0], F_SETFL, ::fcntl(p[0], F_GETFL) | O_NONBLOCK);
      ok = ::dup2(p[0], 0) == 0;
      ::close(p[0]);
      other = p[1];
      break;
    }
    case 2: {
      const int fd = ::memfd_create("fuzz_stdin", MFD_CLOEXEC);
      if (fd < 0) return 0;
      write_all(fd, payload, payload.size() + 1);
      const std::size_t offset = std::min<std::size_t>(m >> 3, payload.size());
      ::lseek(fd, static_cast<off_t>(offset), SEEK_SET);
      expected = payload.substr(offset);
      ok = ::dup2(fd, 0) == 0;
      ::close(fd);
      break;
    }
    case 3: {
      int sv[2];
      if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) return 0;
      ok = ::dup2(sv[0], 0) == 0;
      ::close(sv[0]);
      other = sv[1];
      break;
    }
    case 4:
    case 6: {
      const int fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
      if (fd < 0) return 0;
      ok = ::dup2(fd, 0) == 0;
      ::close(fd);
      expected.clear();
      if (kind == 6) cmr::note_stdin_closed();
      break;
    }
    case 5:
      ::close(0);  // nothing is opened from here to the read: 0 stays closed
      expected.clear();
      break;
  }
  if (!ok) fail();
  if (other >= 0) {
    // What fits in the pipe or socket is written before the read, and the
    // rest by a thread (at nice 19 on the loaded VM every hand-over between
    // two threads cost milliseconds: 4 runs a second with a thread for each
    // input). The non-blocking pipe always gets its bytes from a thread, so
    // that the reader finds it empty and waits (EAGAIN, poll).
    const std::size_t chunk = std::size_t{1} << (4 + (m >> 3) % 13);
    std::string_view rest = payload;
    if (kind != 1) {
      ::fcntl(other, F_SETFL, ::fcntl(other, F_GETFL) | O_NONBLOCK);
      rest = write_all(other, rest, chunk);
      ::fcntl(other, F_SETFL, ::fcntl(other, F_GETFL) & ~O_NONBLOCK);
    }
    if (rest.empty() && kind != 1) {
      ::close(other);
    } else {
      writer = std::thread([other, chunk, rest] {
        (void)write_all(other, rest, chunk);
        ::close(other);
      });
    }
  }

  const bool by_path = kind == 7;
  const std::string name = by_path ? "/dev/stdin" : "stdin";
  const bool closed = kind == 5 || kind == 6;
  std::string text;
  bool read = false;
  try {
    text = cmr::read_input_file(by_path ? "/dev/stdin" : cmr::kStdinPath);
    read = true;
  } catch (const cmr::InputError& e) {
    const std::string what = e.what();
    check_message(what, name);
    // Refused only when it should be, and with the documented line.
    if (closed) {
      if (!starts_with(what, "stdin: closed (")) fail();
    } else if (!expected.empty() || (!starts_with(what, name + ": empty (nothing to read)") &&
                                     !starts_with(what, name + ": empty (nothing came through the FIFO)"))) {
      fail();
    }
  }
  if (read && (closed || text != expected)) fail();
  if (read && !by_path) {
    // Read once per process: "-" again gives the same text.
    if (cmr::read_input_file(cmr::kStdinPath) != text) fail();
    read_as_cmr_analyze_does();
  }

  // Put the fuzzer's descriptor 0 back; that closes the reading end, so a
  // writer still writing gets EPIPE and ends.
  if (::dup2(g_saved_stdin, 0) != 0) fail();
  if (writer.joinable()) writer.join();
  return 0;
}

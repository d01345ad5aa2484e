#include "udp_socket.h"

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

namespace atmo::cigi_ig {

namespace {

std::string system_error(const char* call) { return std::string(call) + ": " + std::strerror(errno); }

}  // namespace

bool parse_ipv4(const std::string& address, uint16_t port, sockaddr_in* out, std::string* error) {
  *out = sockaddr_in{};
  out->sin_family = AF_INET;
  out->sin_port = htons(port);
  if (inet_pton(AF_INET, address.c_str(), &out->sin_addr) != 1) {
    if (error) *error = "'" + address + "' is not an IPv4 address (e.g. 127.0.0.1)";
    return false;
  }
  return true;
}

std::string to_string(const sockaddr_in& address) {
  char text[INET_ADDRSTRLEN] = "?";
  inet_ntop(AF_INET, &address.sin_addr, text, sizeof text);
  return std::string(text) + ":" + std::to_string(ntohs(address.sin_port));
}

UdpSocket::~UdpSocket() {
  if (fd_ >= 0) close(fd_);
}

bool UdpSocket::open(const std::string& address, uint16_t port, std::string* error) {
  sockaddr_in local;
  if (!parse_ipv4(address, port, &local, error)) return false;
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) {
    if (error) *error = system_error("socket");
    return false;
  }
  if (bind(fd_, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
    if (error) *error = system_error(("bind " + to_string(local)).c_str());
    close(fd_);
    fd_ = -1;
    return false;
  }
  return true;
}

uint16_t UdpSocket::local_port() const {
  sockaddr_in local{};
  socklen_t size = sizeof local;
  if (fd_ < 0 || getsockname(fd_, reinterpret_cast<sockaddr*>(&local), &size) != 0) return 0;
  return ntohs(local.sin_port);
}

UdpSocket::Wait UdpSocket::receive(double timeout_s, std::vector<uint8_t>* bytes, sockaddr_in* from,
                                   std::string* error) {
  pollfd p{fd_, POLLIN, 0};
  const int ms = timeout_s <= 0 ? 0 : static_cast<int>(std::ceil(std::min(timeout_s, 2.0e6) * 1000.0));
  const int ready = poll(&p, 1, ms);
  if (ready == 0) return Wait::Timeout;
  if (ready < 0) {
    if (errno == EINTR) return Wait::Interrupted;
    if (error) *error = system_error("poll");
    return Wait::Error;
  }
  bytes->resize(65536);  // above UDP's largest payload (65 507 bytes over IPv4)
  socklen_t size = sizeof *from;
  const ssize_t n = recvfrom(fd_, bytes->data(), bytes->size(), 0, reinterpret_cast<sockaddr*>(from), &size);
  if (n < 0) {
    if (errno == EINTR) return Wait::Interrupted;
    if (error) *error = system_error("recvfrom");
    return Wait::Error;
  }
  bytes->resize(static_cast<size_t>(n));
  return Wait::Datagram;
}

bool UdpSocket::send_to(const sockaddr_in& to, const std::vector<uint8_t>& bytes, std::string* error) {
  const ssize_t n = sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
  if (n != static_cast<ssize_t>(bytes.size())) {
    if (error) *error = system_error(("sendto " + to_string(to)).c_str());
    return false;
  }
  return true;
}

}  // namespace atmo::cigi_ig

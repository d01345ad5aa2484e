// udp_socket.h — the one POSIX UDP socket the CIGI sample IG and its host
// emulator each hold: bound to an IPv4 address (port 0: an ephemeral one),
// datagrams in with a bounded wait, datagrams out to an address.
#pragma once

#include <netinet/in.h>

#include <cstdint>
#include <string>
#include <vector>

namespace atmo::cigi_ig {

// "127.0.0.1" and a port as a socket address; false with *error naming the text.
bool parse_ipv4(const std::string& address, uint16_t port, sockaddr_in* out, std::string* error);
std::string to_string(const sockaddr_in& address);  // "127.0.0.1:5000"

class UdpSocket {
 public:
  UdpSocket() = default;
  ~UdpSocket();
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  // Creates the socket and binds it; false with *error saying which call failed and why.
  bool open(const std::string& address, uint16_t port, std::string* error);
  uint16_t local_port() const;  // the bound port (the ephemeral one for port 0)

  enum class Wait { Datagram, Timeout, Interrupted, Error };
  // Waits at most timeout_s for one datagram (a signal ends the wait early:
  // Interrupted). *bytes holds it whole: any UDP payload fits.
  Wait receive(double timeout_s, std::vector<uint8_t>* bytes, sockaddr_in* from, std::string* error);
  bool send_to(const sockaddr_in& to, const std::vector<uint8_t>& bytes, std::string* error);

 private:
  int fd_ = -1;
};

}  // namespace atmo::cigi_ig

#pragma once
// The far end of the OpenIGTLink tests, written on libOpenIGTLink (what 3D Slicer and PLUS use):
// messages packed by it as bytes, bytes unpacked by it (CRC checked), and a peer on loopback that
// connects to (or accepts) the bridge and reads what it sends.
#include <igtlClientSocket.h>
#include <igtlImageMessage.h>
#include <igtlMessageHeader.h>
#include <igtlPointMessage.h>
#include <igtlPositionMessage.h>
#include <igtlServerSocket.h>
#include <igtlStatusMessage.h>
#include <igtlStringMessage.h>
#include <igtlTransformMessage.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace cobra::bridges::test {

inline std::vector<std::uint8_t> bytesOf(::igtl::MessageBase* message) {
  message->Pack();
  const auto* p = static_cast<const std::uint8_t*>(message->GetPackPointer());
  return {p, p + message->GetPackSize()};
}

/// TRANSFORM `device`: rotation about z by `angle` (rad), translation (mm).
inline std::vector<std::uint8_t> transformBytes(const std::string& device, float angle, float x, float y, float z) {
  ::igtl::TransformMessage::Pointer m = ::igtl::TransformMessage::New();
  m->SetDeviceName(device.c_str());
  ::igtl::Matrix4x4 matrix;
  ::igtl::IdentityMatrix(matrix);
  matrix[0][0] = std::cos(angle);
  matrix[0][1] = -std::sin(angle);
  matrix[1][0] = std::sin(angle);
  matrix[1][1] = std::cos(angle);
  matrix[0][3] = x;
  matrix[1][3] = y;
  matrix[2][3] = z;
  m->SetMatrix(matrix);
  return bytesOf(m.GetPointer());
}

struct PeerPoint {
  std::string name, group;
  float x, y, z;  // mm
};
inline std::vector<std::uint8_t> pointBytes(const std::string& device, const std::vector<PeerPoint>& points) {
  ::igtl::PointMessage::Pointer m = ::igtl::PointMessage::New();
  m->SetDeviceName(device.c_str());
  for (const PeerPoint& p : points) {
    ::igtl::PointElement::Pointer e = ::igtl::PointElement::New();
    e->SetName(p.name.c_str());
    e->SetGroupName(p.group.c_str());
    e->SetPosition(p.x, p.y, p.z);
    m->AddPointElement(e);
  }
  return bytesOf(m.GetPointer());
}

inline std::vector<std::uint8_t> stringBytes(const std::string& device, const std::string& text) {
  ::igtl::StringMessage::Pointer m = ::igtl::StringMessage::New();
  m->SetDeviceName(device.c_str());
  m->SetString(text.c_str());
  return bytesOf(m.GetPointer());
}

inline std::vector<std::uint8_t> statusBytes(const std::string& device, int code, long subcode, const std::string& error,
                                             const std::string& text) {
  ::igtl::StatusMessage::Pointer m = ::igtl::StatusMessage::New();
  m->SetDeviceName(device.c_str());
  m->SetCode(code);
  m->SetSubCode(subcode);
  m->SetErrorName(error.c_str());
  m->SetStatusString(text.c_str());
  return bytesOf(m.GetPointer());
}

/// A POSITION message: a valid OpenIGTLink type the bridge does not take.
inline std::vector<std::uint8_t> positionBytes(const std::string& device) {
  ::igtl::PositionMessage::Pointer m = ::igtl::PositionMessage::New();
  m->SetDeviceName(device.c_str());
  m->SetPosition(1.0F, 2.0F, 3.0F);
  return bytesOf(m.GetPointer());
}

/// Unpacks `bytes` (one whole message) into a new message of type M with libOpenIGTLink, CRC
/// checked; null when the header's type is not M's or the body does not unpack.
template <class M>
typename M::Pointer unpack(const std::vector<std::uint8_t>& bytes) {
  ::igtl::MessageHeader::Pointer header = ::igtl::MessageHeader::New();
  header->InitPack();
  if (bytes.size() < static_cast<std::size_t>(header->GetPackSize())) return nullptr;
  std::memcpy(header->GetPackPointer(), bytes.data(), header->GetPackSize());
  header->Unpack();
  typename M::Pointer m = M::New();
  m->SetMessageHeader(header);
  m->AllocatePack();
  if (bytes.size() != static_cast<std::size_t>(header->GetPackSize() + m->GetPackBodySize())) return nullptr;
  std::memcpy(m->GetPackBodyPointer(), bytes.data() + header->GetPackSize(), m->GetPackBodySize());
  if ((m->Unpack(1) & ::igtl::MessageHeader::UNPACK_BODY) == 0) return nullptr;
  return m;
}

/// Reads one whole message from `socket` (blocking up to the socket's timeout): header and body
/// bytes, or empty when the socket closed or timed out.
inline std::vector<std::uint8_t> receiveMessage(::igtl::Socket* socket, std::string& type, std::string& device) {
  ::igtl::MessageHeader::Pointer header = ::igtl::MessageHeader::New();
  header->InitPack();
  if (socket->Receive(header->GetPackPointer(), header->GetPackSize()) != header->GetPackSize()) return {};
  // The wire bytes, before Unpack turns the header's fields to host byte order in place.
  std::vector<std::uint8_t> bytes(static_cast<const std::uint8_t*>(header->GetPackPointer()),
                                  static_cast<const std::uint8_t*>(header->GetPackPointer()) + header->GetPackSize());
  header->Unpack();
  type = header->GetDeviceType();
  device = header->GetDeviceName();
  const std::size_t body = static_cast<std::size_t>(header->GetBodySizeToRead());
  bytes.resize(bytes.size() + body);
  if (body > 0 && socket->Receive(bytes.data() + header->GetPackSize(), static_cast<int>(body)) != static_cast<int>(body))
    return {};
  return bytes;
}

}  // namespace cobra::bridges::test

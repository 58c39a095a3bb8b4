#pragma once
// ROS 1 bags (format 2.0) built byte by byte from the specification
// (wiki.ros.org/Bags/Format/2.0), independent of io/bag: for the error tests, whose bags must be
// broken in exact places, and for the fuzz seeds. Chunks are stored uncompressed; `compression`
// is written as given, so an unknown one can be named.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace dammloam::test {

struct Ros1Connection {
  std::uint32_t id = 0;
  std::string topic, type;
};

struct Ros1Message {
  std::uint32_t conn = 0;
  std::uint32_t sec = 0, nsec = 0;
  std::string data;
};

template <typename T>
std::string Ros1Le(T value) {
  std::string s(sizeof(T), '\0');
  std::memcpy(s.data(), &value, sizeof(T));
  return s;
}

inline std::string Ros1Header(const std::vector<std::pair<std::string, std::string>>& fields) {
  std::string h;
  for (const auto& [name, value] : fields) {
    h += Ros1Le<std::uint32_t>(static_cast<std::uint32_t>(name.size() + 1 + value.size()));
    h += name + "=" + value;
  }
  return h;
}

inline std::string Ros1Record(const std::vector<std::pair<std::string, std::string>>& fields,
                              const std::string& data) {
  const std::string h = Ros1Header(fields);
  return Ros1Le<std::uint32_t>(static_cast<std::uint32_t>(h.size())) + h +
         Ros1Le<std::uint32_t>(static_cast<std::uint32_t>(data.size())) + data;
}

inline std::string Ros1ConnectionRecord(const Ros1Connection& c) {
  return Ros1Record({{"op", std::string(1, '\x07')}, {"conn", Ros1Le(c.id)}, {"topic", c.topic}},
                    Ros1Header({{"topic", c.topic}, {"type", c.type}, {"md5sum", "*"},
                                {"message_definition", ""}}));
}

inline std::string Ros1Time(std::uint32_t sec, std::uint32_t nsec) { return Ros1Le(sec) + Ros1Le(nsec); }

// A bag with `per_chunk` messages per chunk and the index section (or index_pos 0 when
// `indexed` is false, as a bag whose recording was cut off). `compress` turns a chunk's records
// into the chunk data (identity: stored, whatever `compression` says).
inline std::string BuildRos1Bag(const std::vector<Ros1Connection>& connections,
                                const std::vector<Ros1Message>& messages,
                                const std::string& compression = "none", std::size_t per_chunk = 2,
                                bool indexed = true,
                                const std::function<std::string(const std::string&)>& compress = {}) {
  std::string body;
  std::string chunk_infos;
  std::uint32_t chunks = 0;
  const std::size_t header_size = 4096 + 13;  // the bag header record is padded to 4096 bytes
  for (std::size_t first = 0; first < messages.size(); first += per_chunk) {
    std::string chunk;
    std::vector<std::uint32_t> seen;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> counts;
    for (std::size_t i = first; i < std::min(messages.size(), first + per_chunk); ++i) {
      const Ros1Message& m = messages[i];
      bool known = false;
      for (auto& [conn, count] : counts) {
        if (conn == m.conn) {
          ++count;
          known = true;
        }
      }
      if (!known) {
        counts.emplace_back(m.conn, 1);
        for (const Ros1Connection& c : connections) {
          if (c.id == m.conn) chunk += Ros1ConnectionRecord(c);
        }
      }
      chunk += Ros1Record({{"op", std::string(1, '\x02')}, {"conn", Ros1Le(m.conn)}, {"time", Ros1Time(m.sec, m.nsec)}},
                          m.data);
    }
    const std::uint64_t chunk_pos = header_size + body.size();
    body += Ros1Record({{"op", std::string(1, '\x05')}, {"compression", compression},
                        {"size", Ros1Le<std::uint32_t>(static_cast<std::uint32_t>(chunk.size()))}},
                       compress ? compress(chunk) : chunk);
    std::string info_data;
    for (const auto& [conn, count] : counts) {
      body += Ros1Record({{"op", std::string(1, '\x04')}, {"ver", Ros1Le<std::uint32_t>(1)}, {"conn", Ros1Le(conn)},
                          {"count", Ros1Le(count)}},
                         std::string(12 * count, '\0'));
      info_data += Ros1Le(conn) + Ros1Le(count);
    }
    chunk_infos += Ros1Record({{"op", std::string(1, '\x06')}, {"ver", Ros1Le<std::uint32_t>(1)},
                               {"chunk_pos", Ros1Le(chunk_pos)}, {"start_time", Ros1Time(0, 0)},
                               {"end_time", Ros1Time(0, 0)},
                               {"count", Ros1Le<std::uint32_t>(static_cast<std::uint32_t>(counts.size()))}},
                              info_data);
    ++chunks;
  }
  const std::uint64_t index_pos = indexed ? header_size + body.size() : 0;
  std::string index;
  for (const Ros1Connection& c : connections) index += Ros1ConnectionRecord(c);
  index += chunk_infos;
  std::string header = Ros1Header({{"op", std::string(1, '\x03')}, {"index_pos", Ros1Le(index_pos)},
                                   {"conn_count", Ros1Le<std::uint32_t>(static_cast<std::uint32_t>(connections.size()))},
                                   {"chunk_count", Ros1Le(chunks)}});
  const std::string padding(4096 - 8 - header.size(), ' ');
  std::string bag = "#ROSBAG V2.0\n" + Ros1Le<std::uint32_t>(static_cast<std::uint32_t>(header.size())) + header +
                    Ros1Le<std::uint32_t>(static_cast<std::uint32_t>(padding.size())) + padding;
  return bag + body + (indexed ? index : std::string());
}

// sensor_msgs/PointCloud2 in the ROS 1 serialisation: fields x y z intensity (float32), n points.
inline std::string Ros1PointCloud2(std::uint32_t seq, std::uint32_t sec, std::uint32_t nsec,
                                   const std::vector<float>& xyzi) {
  auto str = [](const std::string& s) { return Ros1Le<std::uint32_t>(static_cast<std::uint32_t>(s.size())) + s; };
  const auto n = static_cast<std::uint32_t>(xyzi.size() / 4);
  std::string m = Ros1Le(seq) + Ros1Time(sec, nsec) + str("lidar") + Ros1Le<std::uint32_t>(1) + Ros1Le(n);
  m += Ros1Le<std::uint32_t>(4);
  const char* names[] = {"x", "y", "z", "intensity"};
  for (std::uint32_t k = 0; k < 4; ++k) {
    m += str(names[k]) + Ros1Le<std::uint32_t>(4 * k) + std::string(1, '\x07') + Ros1Le<std::uint32_t>(1);
  }
  m += std::string(1, '\0') + Ros1Le<std::uint32_t>(16) + Ros1Le<std::uint32_t>(16 * n);
  std::string data(xyzi.size() * 4, '\0');
  if (!xyzi.empty()) std::memcpy(data.data(), xyzi.data(), data.size());
  m += str(data) + std::string(1, '\x01');
  return m;
}

}  // namespace dammloam::test

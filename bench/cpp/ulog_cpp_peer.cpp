// PX4's C++ reader (ulog_cpp) on the harness's workloads, through its public API.
// Built by bench/run against the ulog_cpp source in the peers folder (never copied
// into this repository):
//
//   ulog_cpp_peer stream FILE   Reader + a DataContainer that keeps only the header
//                               (StorageConfig::Header); every field of every data
//                               message read as a typed Value and summed, streaming
//   ulog_cpp_peer load FILE     Reader + DataContainer(StorageConfig::FullLog): every
//                               message kept in memory (its "load everything")
//
// Both read the file with fread in 256 KiB chunks (its examples use 4 KiB) and print
// `messages=N check=X` like the other programs.

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <ulog_cpp/data_container.hpp>
#include <ulog_cpp/reader.hpp>

namespace {

using ulog_cpp::Field;
using ulog_cpp::Value;

double sum_field(const Value& value, const Field& field);

// A nested field's members, at one element of it (or the whole of it, not an array).
double sum_nested(const Value& element, const Field& field)
{
  double sum = 0;
  for (const auto& member : field.type().nested_message->fields()) {
    if (member->name().rfind("_padding", 0) == 0) {
      continue;
    }
    sum += sum_field(element[*member], *member);
  }
  return sum;
}

double sum_field(const Value& value, const Field& field)
{
  const auto type = field.type().type;
  if (type == Field::BasicType::NESTED) {
    if (field.arrayLength() < 0) {
      return sum_nested(value, field);
    }
    double sum = 0;
    for (int i = 0; i < field.arrayLength(); i++) {
      sum += sum_nested(value[static_cast<size_t>(i)], field);
    }
    return sum;
  }
  if (type == Field::BasicType::CHAR) {
    if (field.arrayLength() < 0) {
      return static_cast<double>(value.as<uint8_t>());
    }
    return static_cast<double>(value.as<std::string>().size());
  }
  if (field.arrayLength() < 0) {
    return value.as<double>();
  }
  // Element by element: about 0.94x the time of `as<std::vector<double>>()`, which
  // allocates a vector per array (5 interleaved pairs, sample_px4_events x 200).
  double sum = 0;
  for (int i = 0; i < field.arrayLength(); i++) {
    sum += value[static_cast<size_t>(i)].as<double>();
  }
  return sum;
}

// Keeps the header only (its Header storage drops subscriptions added after the
// header, so they are kept here, by message id, as its streaming example keeps them),
// and sums every field of each data message as it arrives.
class Summing : public ulog_cpp::DataContainer {
 public:
  Summing() : ulog_cpp::DataContainer(ulog_cpp::DataContainer::StorageConfig::Header) {}

  void addLoggedMessage(const ulog_cpp::AddLoggedMessage& add) override
  {
    DataContainer::addLoggedMessage(add);
    const auto format = messageFormats().find(add.messageName());
    if (format == messageFormats().end()) {
      throw ulog_cpp::ParsingException("AddLoggedMessage message format not found");
    }
    if (formats.size() <= add.msgId()) {
      formats.resize(add.msgId() + 1);
    }
    formats[add.msgId()] = format->second;
  }

  void data(const ulog_cpp::Data& data) override
  {
    if (data.msgId() >= formats.size() || !formats[data.msgId()]) {
      return;
    }
    const auto& format = *formats[data.msgId()];
    messages++;
    const ulog_cpp::TypedDataView view(data, format);
    for (const auto& field : format.fields()) {
      // Padding is not a value (and PX4 leaves the trailing padding out of the payload,
      // which ulog_cpp's Value refuses to read).
      if (field->name().rfind("_padding", 0) == 0) {
        continue;
      }
      // Eight partial sums, a field to each in turn, as the other peers sum.
      sums[next++ & 7] += sum_field(view.at(*field), *field);
    }
  }

  std::vector<std::shared_ptr<ulog_cpp::MessageFormat>> formats;
  unsigned long long messages = 0;
  double sums[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  unsigned next = 0;
};

// Feeds the file to a Reader over `container` in 256 KiB reads; false (said on stderr)
// when the file cannot be opened or ulog_cpp reports a fatal parsing error.
bool read_all(const char* path, const std::shared_ptr<ulog_cpp::DataContainer>& container)
{
  FILE* file = std::fopen(path, "rb");
  if (file == nullptr) {
    std::fprintf(stderr, "cannot open %s\n", path);
    return false;
  }
  ulog_cpp::Reader reader{container};
  std::vector<uint8_t> buffer(256 * 1024);
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), file)) > 0) {
    reader.readChunk(buffer.data(), static_cast<int>(n));
  }
  std::fclose(file);
  if (container->hadFatalError()) {
    std::fprintf(stderr, "ulog_cpp: fatal parsing error\n");
    return false;
  }
  return true;
}

int stream(const char* path)
{
  auto container = std::make_shared<Summing>();
  if (!read_all(path, container)) {
    return 1;
  }
  double sum = 0;
  for (double s : container->sums) {
    sum += s;
  }
  std::printf("messages=%llu check=%g\n", container->messages, sum);
  return 0;
}

int load(const char* path)
{
  auto container =
      std::make_shared<ulog_cpp::DataContainer>(ulog_cpp::DataContainer::StorageConfig::FullLog);
  if (!read_all(path, container)) {
    return 1;
  }
  unsigned long long messages = 0;
  unsigned long long bytes = 0;
  for (const auto& kv : container->subscriptionsByMessageId()) {
    messages += kv.second->size();
    for (const auto& sample : kv.second->rawSamples()) {
      bytes += sample.data().size();
    }
  }
  std::printf("messages=%llu check=%llu\n", messages, bytes);
  return 0;
}

}  // namespace

int main(int argc, char** argv)
{
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s stream|load FILE\n", argv[0]);
    return 2;
  }
  const std::string mode = argv[1];
  try {
    if (mode == "stream") {
      return stream(argv[2]);
    }
    if (mode == "load") {
      return load(argv[2]);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ulog_cpp: %s\n", e.what());
    return 1;
  }
  std::fprintf(stderr, "unknown mode %s\n", argv[1]);
  return 2;
}

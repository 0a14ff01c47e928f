#include "hbf/diagnostics.hpp"

#include <glog/logging.h>

#include <mutex>

namespace hbf {

namespace {
std::mutex& guard() {
    static std::mutex m;
    return m;
}
LibraryMessages& store() {
    static LibraryMessages messages;
    return messages;
}

/// Counts glog messages of severity WARNING and above (Ceres' INFO lines are progress, not
/// diagnostics).
class CountingSink : public google::LogSink {
public:
    void send(google::LogSeverity severity, const char*, const char* base_filename, int line,
              const google::LogMessageTime&, const char* message, std::size_t length) override {
        if (severity < google::GLOG_WARNING) return;
        detail::record_library_message("ceres", std::string(message, length) + " (" + base_filename + ":" +
                                                    std::to_string(line) + ")");
    }
};
}  // namespace

void capture_library_messages() {
    static std::once_flag once;
    std::call_once(once, [] {
        if (!google::IsGoogleLoggingInitialized()) {
            // Before InitGoogleLogging glog prints everything to stderr; after it, to log files
            // in /tmp and, from ERROR up, to stderr. Neither: no file destinations, no stderr.
            google::InitGoogleLogging("hbfriction");
            for (google::LogSeverity s : {google::GLOG_INFO, google::GLOG_WARNING, google::GLOG_ERROR, google::GLOG_FATAL})
                google::SetLogDestination(s, "");
            FLAGS_logtostderr = false;
            FLAGS_alsologtostderr = false;
            FLAGS_stderrthreshold = google::NUM_SEVERITIES;
        }
        static CountingSink sink;
        google::AddLogSink(&sink);
    });
}

LibraryMessages library_messages() {
    std::lock_guard<std::mutex> lock(guard());
    return store();
}

void reset_library_messages() {
    std::lock_guard<std::mutex> lock(guard());
    store() = LibraryMessages{};
}

namespace detail {
void record_library_message(const std::string& source, const std::string& text) {
    std::lock_guard<std::mutex> lock(guard());
    LibraryMessages& m = store();
    if (m.count++ == 0) m.first = source + ": " + text;
}
}  // namespace detail

}  // namespace hbf

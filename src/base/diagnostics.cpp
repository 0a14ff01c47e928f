// hbfriction — the libraries' messages (Ceres through glog, CVODE) collected per computation
// (diagnostics.hpp).
#include "hbf/diagnostics.hpp"

#include <glog/logging.h>

#include <mutex>

namespace hbf {

namespace {
/// This thread's innermost collector (none: messages are not counted).
thread_local MessageCollector* innermost = nullptr;

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

void LibraryMessages::add(const LibraryMessages& other) {
    if (count == 0) first = other.first;
    count += other.count;
    step_failures += other.step_failures;
}

MessageCollector::MessageCollector() : enclosing_(innermost) { innermost = this; }

MessageCollector::~MessageCollector() {
    innermost = enclosing_;
    if (enclosing_ != nullptr) enclosing_->messages_.add(messages_);
}

namespace detail {
void record_library_message(const std::string& source, const std::string& text) {
    if (innermost == nullptr) return;
    LibraryMessages& m = innermost->messages_;
    if (m.count++ == 0) m.first = source + ": " + text;
    if (source == "ceres" && text.find("Linear solver failure") != std::string::npos) ++m.step_failures;
}
}  // namespace detail

}  // namespace hbf

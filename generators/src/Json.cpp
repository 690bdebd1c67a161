#include "Json.h"

#include <cmath>
#include <cstdio>

namespace wirenet {

Json& Json::set(const std::string& key, Json value) {
    for (auto& kv : items_)
        if (kv.first == key) {
            kv.second = std::move(value);
            return *this;
        }
    items_.emplace_back(key, std::move(value));
    return *this;
}

Json& Json::push(Json value) {
    elems_.push_back(std::move(value));
    return *this;
}

static void writeString(std::string& out, const std::string& s) {
    out += '"';
    for (unsigned char c : s) {
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\t': out += "\\t"; break;
            default:
                if (c < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", c);
                    out += buf;
                } else {
                    out += char(c);
                }
        }
    }
    out += '"';
}

void Json::write(std::string& out, int indent, int level) const {
    auto newline = [&](int lvl) {
        if (indent > 0) out += "\n" + std::string(size_t(indent * lvl), ' ');
    };
    switch (type_) {
        case Type::Null: out += "null"; break;
        case Type::Bool: out += bool_ ? "true" : "false"; break;
        case Type::Number: {
            if (!std::isfinite(num_)) { out += "null"; break; }
            char buf[64];
            std::snprintf(buf, sizeof buf, "%.15g", num_);
            out += buf;
            break;
        }
        case Type::String: writeString(out, str_); break;
        case Type::Array: {
            // Short numeric arrays (vectors, tensors rows) stay on one line.
            bool flat = true;
            for (const auto& e : elems_) flat = flat && e.type_ != Type::Object && e.type_ != Type::Array;
            out += '[';
            for (size_t i = 0; i < elems_.size(); ++i) {
                if (i) out += flat ? ", " : ",";
                if (!flat) newline(level + 1);
                elems_[i].write(out, indent, level + 1);
            }
            if (!flat && !elems_.empty()) newline(level);
            out += ']';
            break;
        }
        case Type::Object: {
            out += '{';
            for (size_t i = 0; i < items_.size(); ++i) {
                if (i) out += ',';
                newline(level + 1);
                writeString(out, items_[i].first);
                out += ": ";
                items_[i].second.write(out, indent, level + 1);
            }
            if (!items_.empty()) newline(level);
            out += '}';
            break;
        }
    }
}

std::string Json::dump(int indent) const {
    std::string out;
    write(out, indent, 0);
    return out;
}

}  // namespace wirenet

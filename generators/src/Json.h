// Minimal ordered JSON value for the metadata files (no external dependency).
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace wirenet {

class Json {
public:
    enum class Type { Null, Bool, Number, String, Array, Object };

    Json() = default;
    Json(double v) : type_(Type::Number), num_(v) {}
    Json(int v) : type_(Type::Number), num_(v) {}
    Json(long v) : type_(Type::Number), num_(double(v)) {}
    Json(bool v) : type_(Type::Bool), bool_(v) {}
    Json(const char* s) : type_(Type::String), str_(s) {}
    Json(std::string s) : type_(Type::String), str_(std::move(s)) {}
    static Json object() { Json j; j.type_ = Type::Object; return j; }
    static Json array() { Json j; j.type_ = Type::Array; return j; }
    template <class V>
    static Json vec3(const V& v) {
        Json a = array();
        for (int i = 0; i < 3; ++i) a.push(double(v[i]));
        return a;
    }

    // Object: sets (replaces) a key, keeping insertion order.
    Json& set(const std::string& key, Json value);
    Json& push(Json value);
    bool empty() const { return items_.empty() && elems_.empty(); }
    // An object's keys and values in insertion order.
    const std::vector<std::pair<std::string, Json>>& items() const { return items_; }
    std::string dump(int indent = 0) const;

private:
    void write(std::string& out, int indent, int level) const;
    Type type_ = Type::Null;
    double num_ = 0;
    bool bool_ = false;
    std::string str_;
    std::vector<std::pair<std::string, Json>> items_;
    std::vector<Json> elems_;
};

}  // namespace wirenet

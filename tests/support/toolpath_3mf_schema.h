// Validating a 3MF toolpath package's toolpath resource and layer parts against an XSD with
// libxml2 (tests/schema/toolpath_3mf.xsd, or the specification's own file).
#pragma once

#include <gtest/gtest.h>
#include <libxml/parser.h>
#include <libxml/xmlschemas.h>

#include <map>
#include <memory>
#include <string>
#include <string_view>

namespace polyaxis::test {

// The errors of the toolpath resource of PARTS' model and of every layer part against the schema
// in XSD_PATH (libxml2 prints what they are on stderr).
inline int toolpath_schema_errors(const std::string& xsd_path, const std::map<std::string, std::string>& parts) {
  struct DocFree {
    void operator()(xmlDoc* d) const { xmlFreeDoc(d); }
  };
  auto parse = [](const std::string& xml) {
    return std::unique_ptr<xmlDoc, DocFree>(xmlReadMemory(xml.data(), static_cast<int>(xml.size()), nullptr, nullptr, XML_PARSE_NONET));
  };
  xmlSchemaParserCtxtPtr pc = xmlSchemaNewParserCtxt(xsd_path.c_str());
  xmlSchemaPtr schema = xmlSchemaParse(pc);
  xmlSchemaFreeParserCtxt(pc);
  EXPECT_NE(schema, nullptr) << xsd_path;
  if (schema == nullptr) return 1;
  xmlSchemaValidCtxtPtr vc = xmlSchemaNewValidCtxt(schema);
  int errors = 0, layers = 0, resources = 0;
  for (const auto& [path, bytes] : parts) {
    if (path == "3D/3dmodel.model") {
      auto doc = parse(bytes);
      if (doc == nullptr) {
        ++errors;
        continue;
      }
      for (xmlNode* c = xmlDocGetRootElement(doc.get())->children; c != nullptr; c = c->next) {
        if (c->type != XML_ELEMENT_NODE || std::string_view(reinterpret_cast<const char*>(c->name)) != "resources") continue;
        for (xmlNode* r = c->children; r != nullptr; r = r->next) {
          if (r->type != XML_ELEMENT_NODE || std::string_view(reinterpret_cast<const char*>(r->name)) != "toolpathresource") continue;
          ++resources;
          if (xmlSchemaValidateOneElement(vc, r) != 0) ++errors;
        }
      }
    } else if (path.rfind("Toolpath/Layers/", 0) == 0) {
      ++layers;
      auto doc = parse(bytes);
      if (doc == nullptr || xmlSchemaValidateDoc(vc, doc.get()) != 0) ++errors;
    }
  }
  EXPECT_EQ(resources, 1);
  EXPECT_GT(layers, 0);
  xmlSchemaFreeValidCtxt(vc);
  xmlSchemaFree(schema);
  return errors;
}

}  // namespace polyaxis::test

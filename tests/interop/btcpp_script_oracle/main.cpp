// btcpp_script_oracle: run scripts with BehaviorTree.CPP 4's own script engine.
//
// usage: btcpp_script_oracle < CASES
//
// Every input line is one script, run in one blackboard shared by all the lines of a case
// ("\n" in a line stands for a newline). Other lines:
//   "#enum NAME VALUE"  registers a scripting enum;
//   "#reset"            starts a new case (a fresh blackboard, no enums).
// Output: one line per script: "NUM <value>" (a number, printed with 17 digits),
// "STR <text>", "EMPTY", "OTHER", "PARSE_ERROR" or "RUN_ERROR".
#include <behaviortree_cpp/blackboard.h>
#include <behaviortree_cpp/scripting/script_parser.hpp>

#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

namespace
{
std::string Unescape(std::string line)
{
  for(size_t at = line.find("\\n"); at != std::string::npos; at = line.find("\\n", at + 1))
  {
    line.replace(at, 2, "\n");
  }
  return line;
}

std::string Describe(const BT::Any& value)
{
  std::ostringstream out;
  if(value.empty())
  {
    out << "EMPTY";
  }
  else if(value.isNumber())
  {
    out << "NUM " << std::setprecision(17) << value.cast<double>();
  }
  else if(value.isString())
  {
    out << "STR " << value.cast<std::string>();
  }
  else
  {
    out << "OTHER";
  }
  return out.str();
}
}  // namespace

int main()
{
  auto blackboard = BT::Blackboard::create();
  auto enums = std::make_shared<BT::EnumsTable>();
  std::string line;
  while(std::getline(std::cin, line))
  {
    if(line == "#reset")
    {
      blackboard = BT::Blackboard::create();
      enums = std::make_shared<BT::EnumsTable>();
      continue;
    }
    if(line.rfind("#enum ", 0) == 0)
    {
      std::istringstream words(line.substr(6));
      std::string name;
      int value = 0;
      words >> name >> value;
      (*enums)[name] = value;
      continue;
    }
    auto function = BT::ParseScript(Unescape(line));
    if(!function)
    {
      std::cout << "PARSE_ERROR" << std::endl;
      continue;
    }
    BT::Ast::Environment environment{ blackboard, enums };
    try
    {
      std::cout << Describe(function.value()(environment)) << std::endl;
    }
    catch(const std::exception&)
    {
      std::cout << "RUN_ERROR" << std::endl;
    }
  }
  return 0;
}

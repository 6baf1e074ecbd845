// btcpp_checker: load an exported tree with BehaviorTree.CPP 4 and tick it with scripted leaves.
//
// usage: btcpp_checker TREE.xml SCRIPT MAX_TICKS [all] [halts] [sleep=MSEC|clock=MSEC] [speed=M/S] [goals=T1,T2..]
//
// Every model of the file's <TreeNodesModel> is registered with its declared ports
// (BehaviorTreeFactory::registerBuilder with a manifest built from the model): an
// Action/Condition model becomes a scripted leaf, a Sar... Decorator the py_trees
// decorator it stands for, a Nav2 control node (RecoveryNode, PipelineSequence,
// RoundRobin, RateController, SingleTrigger, DistanceController, SpeedController,
// GoalUpdatedController, GoalUpdater, PathLongerOnApproach) its stand-in (nav2_standins.h), any other
// Control one that loads but cannot tick. With
// MAX_TICKS 0 the file is only loaded (createTreeFromText: every check BT.CPP makes). SCRIPT has one line per leaf name: "NAME STATUS STATUS ...";
// each visit of that leaf returns the next status, the last one repeats; a leaf without a
// line returns SUCCESS. The tree is ticked until the root is not RUNNING (or MAX_TICKS);
// with "all", MAX_TICKS times (a finished root starts over, as a mission runner ticks it).
// With "halts" every halt of a running leaf prints "halt NAME".
// With "sleep=MSEC" it sleeps MSEC milliseconds after each tick (for Delay, Timeout, Sleep);
// both "sleep=" and "clock=" advance the Nav2 stand-ins' clock (Robot::seconds) by MSEC a tick,
// "clock=" without sleeping.
// Output: "visit NAME STATUS" for every leaf tick and "tick N STATUS" after each tick.
#include <behaviortree_cpp/action_node.h>
#include <behaviortree_cpp/bt_factory.h>
#include <behaviortree_cpp/control_node.h>
#include <behaviortree_cpp/decorator_node.h>
#include <tinyxml2.h>

#include "nav2_standins.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

using BT::NodeStatus;

namespace
{
// Leaf name -> the statuses of its successive visits.
class Script
{
public:
  explicit Script(const std::string& path)
  {
    std::ifstream in(path);
    std::string line;
    while(std::getline(in, line))
    {
      std::istringstream words(line);
      std::string name, word;
      if(!(words >> name))
      {
        continue;
      }
      while(words >> word)
      {
        results_[name].push_back(BT::convertFromString<NodeStatus>(word));
      }
    }
  }

  NodeStatus next(const std::string& name)
  {
    auto found = results_.find(name);
    if(found == results_.end() || found->second.empty())
    {
      return NodeStatus::SUCCESS;
    }
    size_t& index = visits_[name];
    const auto& list = found->second;
    return list[std::min(index++, list.size() - 1)];
  }

private:
  std::map<std::string, std::vector<NodeStatus>> results_;
  std::map<std::string, size_t> visits_;
};

class ScriptedLeaf : public BT::ActionNodeBase
{
public:
  ScriptedLeaf(const std::string& name, const BT::NodeConfig& config, Script& script)
    : BT::ActionNodeBase(name, config), script_(script)
  {}

  NodeStatus tick() override
  {
    const NodeStatus status = script_.next(name());
    std::cout << "visit " << name() << " " << BT::toStr(status) << "\n";
    return status;
  }

  void halt() override
  {
    if(print_halts)
    {
      std::cout << "halt " << name() << "\n";
    }
    resetStatus();
  }

  static inline bool print_halts = false;

private:
  Script& script_;
};

// The py_trees decorators BT.CPP has no built-in for (sar_framework.interop.mapping).
class SarDecorator : public BT::DecoratorNode
{
public:
  SarDecorator(const std::string& name, const BT::NodeConfig& config, std::string kind)
    : BT::DecoratorNode(name, config), kind_(std::move(kind))
  {}

  NodeStatus tick() override
  {
    if(latched_)
    {
      return *latched_;
    }
    setStatus(NodeStatus::RUNNING);
    const NodeStatus child = child_node_->executeTick();
    const NodeStatus result = convert(child);
    if(child != NodeStatus::RUNNING)
    {
      resetChild();
    }
    else if(result != NodeStatus::RUNNING)
    {
      haltChild();
    }
    return result;
  }

  void halt() override
  {
    DecoratorNode::halt();
  }

private:
  NodeStatus convert(NodeStatus child)
  {
    if(kind_ == "SarFailureIsRunning")
      return child == NodeStatus::FAILURE ? NodeStatus::RUNNING : child;
    if(kind_ == "SarRunningIsFailure")
      return child == NodeStatus::RUNNING ? NodeStatus::FAILURE : child;
    if(kind_ == "SarRunningIsSuccess")
      return child == NodeStatus::RUNNING ? NodeStatus::SUCCESS : child;
    if(kind_ == "SarCondition")
    {
      const auto wanted = getInput<std::string>("status").value();
      const bool met = BT::toStr(child) == upper(wanted);
      return met ? NodeStatus::SUCCESS : NodeStatus::RUNNING;
    }
    if(kind_ == "SarOneShot")
    {
      const auto policy = getInput<std::string>("policy").value();
      const bool done = child == NodeStatus::SUCCESS ||
                        (policy == "on_completion" && child == NodeStatus::FAILURE);
      if(done)
      {
        latched_ = child;
      }
      return child;
    }
    if(kind_ == "SarPassThrough" || kind_ == "SarCount")
      return child;
    throw BT::RuntimeError("btcpp_checker: no implementation of ", kind_);
  }

  static std::string upper(std::string text)
  {
    for(auto& c : text)
    {
      c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    return text;
  }

  std::string kind_;
  std::optional<NodeStatus> latched_;
};

// py_trees' Parallel: tick every child (but, with synchronise, those already succeeded),
// then FAILURE if any failed, else SUCCESS when the policy is met, else RUNNING.
class SarParallel : public BT::ControlNode
{
public:
  SarParallel(const std::string& name, const BT::NodeConfig& config)
    : BT::ControlNode(name, config)
  {}

  NodeStatus tick() override
  {
    const auto policy = getInput<std::string>("policy").value();
    const bool synchronise =
        policy != "success_on_one" && getInput<bool>("synchronise").value_or(true);
    if(status() != NodeStatus::RUNNING)
    {
      last_.assign(childrenCount(), NodeStatus::IDLE);
    }
    setStatus(NodeStatus::RUNNING);
    for(size_t i = 0; i < childrenCount(); ++i)
    {
      if(!(synchronise && last_[i] == NodeStatus::SUCCESS))
      {
        last_[i] = children_nodes_[i]->executeTick();
      }
    }
    NodeStatus result = NodeStatus::RUNNING;
    const auto count = [this](NodeStatus wanted) {
      return std::count(last_.begin(), last_.end(), wanted);
    };
    if(count(NodeStatus::FAILURE) > 0)
    {
      result = NodeStatus::FAILURE;
    }
    else if(policy == "success_on_all" && count(NodeStatus::SUCCESS) == long(childrenCount()))
    {
      result = NodeStatus::SUCCESS;
    }
    else if(policy == "success_on_one" && count(NodeStatus::SUCCESS) > 0)
    {
      result = NodeStatus::SUCCESS;
    }
    else if(policy == "success_on_selected" && selectedSucceeded())
    {
      result = NodeStatus::SUCCESS;
    }
    if(result != NodeStatus::RUNNING)
    {
      resetChildren();
    }
    return result;
  }

private:
  bool selectedSucceeded()
  {
    std::istringstream names(getInput<std::string>("selected").value());
    std::string wanted;
    while(std::getline(names, wanted, ';'))
    {
      for(size_t i = 0; i < childrenCount(); ++i)
      {
        if(children_nodes_[i]->name() == wanted && last_[i] != NodeStatus::SUCCESS)
        {
          return false;
        }
      }
    }
    return true;
  }

  std::vector<NodeStatus> last_;
};

template <typename T>
BT::PortInfo typedPort(BT::PortDirection direction, const char* name, const char* def,
                       const char* text)
{
  BT::PortInfo port = direction == BT::PortDirection::INPUT ?
                          BT::InputPort<T>(name, text ? text : "").second :
                      direction == BT::PortDirection::OUTPUT ?
                          BT::OutputPort<T>(name, text ? text : "").second :
                          BT::BidirectionalPort<T>(name, text ? text : "").second;
  if(def != nullptr && BT::TreeNode::isBlackboardPointer(def))
  {
    port.setDefaultValue(std::string(def));
  }
  else if(def != nullptr)
  {
    port.setDefaultValue(BT::convertFromString<T>(def));
  }
  return port;
}

// input_port, output_port and inout_port; a type other than the basic ones (a message,
// or none) is registered untyped, as BT.CPP does for BT::AnyTypeAllowed.
BT::PortsList portsOf(const tinyxml2::XMLElement* model)
{
  BT::PortsList ports;
  const std::pair<const char*, BT::PortDirection> kinds[] = {
    { "input_port", BT::PortDirection::INPUT },
    { "output_port", BT::PortDirection::OUTPUT },
    { "inout_port", BT::PortDirection::INOUT },
  };
  for(const auto& [tag, direction] : kinds)
  {
    for(auto* port = model->FirstChildElement(tag); port != nullptr;
        port = port->NextSiblingElement(tag))
    {
      const char* name = port->Attribute("name");
      const std::string type = port->Attribute("type") ? port->Attribute("type") : "";
      const char* def = port->Attribute("default");
      const char* text = port->GetText();
      if(type == "int")
        ports.insert({ name, typedPort<int>(direction, name, def, text) });
      else if(type == "double")
        ports.insert({ name, typedPort<double>(direction, name, def, text) });
      else if(type == "bool")
        ports.insert({ name, typedPort<bool>(direction, name, def, text) });
      else if(type == "std::string")
        ports.insert({ name, typedPort<std::string>(direction, name, def, text) });
      else
        ports.insert({ name, typedPort<BT::AnyTypeAllowed>(direction, name, nullptr, text) });
    }
  }
  return ports;
}

// A control or decorator the checker has no implementation of: it can be loaded (the
// file is checked), not ticked.
template <typename Base>
class Unimplemented : public Base
{
public:
  Unimplemented(const std::string& name, const BT::NodeConfig& config) : Base(name, config)
  {}

  NodeStatus tick() override
  {
    throw BT::RuntimeError("btcpp_checker: no implementation of ", this->registrationName());
  }
};

// Register every model of the file's <TreeNodesModel>; returns how many.
int registerModels(const std::string& path, BT::BehaviorTreeFactory& factory, Script& script)
{
  tinyxml2::XMLDocument doc;
  if(doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS)
  {
    throw BT::RuntimeError("cannot read ", path, ": ", doc.ErrorStr());
  }
  auto* models = doc.RootElement()->FirstChildElement("TreeNodesModel");
  int count = 0;
  for(auto* model = models ? models->FirstChildElement() : nullptr; model != nullptr;
      model = model->NextSiblingElement())
  {
    const std::string category = model->Name();
    BT::TreeNodeManifest manifest;
    manifest.registration_ID = model->Attribute("ID");
    manifest.ports = portsOf(model);
    if(auto nav2 = nav2_standins::builderFor(manifest.registration_ID))
    {
      manifest.type = category == "Control" ? BT::NodeType::CONTROL : BT::NodeType::DECORATOR;
      factory.registerBuilder(manifest, nav2);
    }
    else if(category == "Action" || category == "Condition")
    {
      manifest.type = BT::NodeType::ACTION;
      factory.registerBuilder(manifest, [&script](const std::string& name,
                                                  const BT::NodeConfig& config) {
        return std::make_unique<ScriptedLeaf>(name, config, script);
      });
    }
    else if(category == "Decorator")
    {
      manifest.type = BT::NodeType::DECORATOR;
      const std::string kind = manifest.registration_ID;
      factory.registerBuilder(manifest, [kind](const std::string& name,
                                               const BT::NodeConfig& config) {
        return std::make_unique<SarDecorator>(name, config, kind);
      });
    }
    else if(category == "Control" && manifest.registration_ID == "SarParallel")
    {
      manifest.type = BT::NodeType::CONTROL;
      factory.registerBuilder(manifest, [](const std::string& name,
                                           const BT::NodeConfig& config) {
        return std::make_unique<SarParallel>(name, config);
      });
    }
    else if(category == "Control")
    {
      manifest.type = BT::NodeType::CONTROL;
      factory.registerBuilder(manifest, [](const std::string& name,
                                           const BT::NodeConfig& config) {
        return std::make_unique<Unimplemented<BT::ControlNode>>(name, config);
      });
    }
    else
    {
      throw BT::RuntimeError("btcpp_checker: no implementation of the ", category, " ",
                             manifest.registration_ID);
    }
    ++count;
  }
  return count;
}

}  // namespace

int main(int argc, char** argv)
{
  bool all_ticks = false;
  int tick_msec = 0;
  bool sleeps = false;
  std::set<int> goal_ticks;
  bool usage = argc < 4;
  for(int i = 4; i < argc; ++i)
  {
    const std::string option = argv[i];
    if(option == "all")
      all_ticks = true;
    else if(option == "halts")
      ScriptedLeaf::print_halts = true;
    else if(option.rfind("goals=", 0) == 0)
    {
      std::stringstream ticks(option.substr(6));
      for(std::string item; std::getline(ticks, item, ',');)
        goal_ticks.insert(std::stoi(item));
    }
    else if(option.rfind("speed=", 0) == 0)
    {
      nav2_standins::Robot::known = true;
      nav2_standins::Robot::speed = std::stod(option.substr(6));
    }
    else if(option.rfind("sleep=", 0) == 0 || option.rfind("clock=", 0) == 0)
    {
      tick_msec = std::stoi(option.substr(6));
      sleeps = option.rfind("sleep=", 0) == 0;
    }
    else
      usage = true;
  }
  if(usage)
  {
    std::cerr << "usage: btcpp_checker TREE.xml SCRIPT MAX_TICKS [all] [halts] [sleep=MSEC|clock=MSEC] [speed=M/S] [goals=T1,T2..]\n";
    return 2;
  }
  try
  {
    Script script(argv[2]);
    BT::BehaviorTreeFactory factory;
    const int models = registerModels(argv[1], factory, script);
    std::ifstream in(argv[1]);
    std::stringstream text;
    text << in.rdbuf();
    auto tree = factory.createTreeFromText(text.str());
    std::cout << "models " << models << "\n";
    const int max_ticks = std::stoi(argv[3]);
    for(int tick = 1; tick <= max_ticks; ++tick)
    {
      nav2_standins::Robot::seconds = (tick - 1) * tick_msec / 1000.0;
      if(goal_ticks.count(tick) > 0)  // a new goal before this tick: "goal N"
      {
        tree.rootBlackboard()->set("goal", "goal " + std::to_string(tick));
      }
      const NodeStatus status = tree.tickExactlyOnce();
      std::cout << "tick " << tick << " " << BT::toStr(status) << "\n";
      if(status != NodeStatus::RUNNING && !all_ticks)
      {
        break;
      }
      if(sleeps && tick_msec > 0)
      {
        std::this_thread::sleep_for(std::chrono::milliseconds(tick_msec));
      }
    }
    ScriptedLeaf::print_halts = false;  // the tree's destructor halts every node
  }
  catch(const std::exception& error)
  {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
  return 0;
}

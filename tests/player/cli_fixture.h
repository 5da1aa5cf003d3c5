// The fixture of `hlod path` and `hlod play` CLI tests (test_cli.cpp, test_cli_path.cpp): a
// synthetic database of three levels in a folder of its own.
#pragma once

#include "tests/support/run_hlod.h"
#include "tests/support/synthetic.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>

class Cli : public ::testing::Test {
protected:
    std::filesystem::path dir;
    std::string db;

    void SetUp() override {
        dir = std::filesystem::temp_directory_path() / ("hlod_cli_player_" + std::to_string(::getpid()) + "_" +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(dir);
        db = (dir / "terrain.hlod").string();
        hlod::SyntheticOptions o;
        o.levels = 3;
        hlod::writeSyntheticDatabase(db, o);
    }
    void TearDown() override { std::filesystem::remove_all(dir); }

    std::string walk() {
        std::string path = (dir / "walk.path").string();
        hlod::test::RunResult r = hlod::test::runHlod({"path", db, "--kind", "walk", "--duration", "5", "-o", path});
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return path;
    }
};

inline int lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

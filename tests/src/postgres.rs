//! A throwaway PostgreSQL server for the tests of the PostgreSQL store: `initdb` into a scratch folder,
//! started with `pg_ctl` listening only on a Unix socket inside that folder (so it needs no
//! free TCP port and nothing outside the folder), stopped and removed on drop.
//!
//! Where no PostgreSQL server binaries are installed, [`Cluster::start`] prints why and
//! returns `None`, and the test says it was skipped; with `BREAKSHOT_REQUIRE_POSTGRES=1` (set
//! by CI, which installs them) it fails instead.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use breakshot_testkit::{run, run_ok};
use tempfile::TempDir;

const LIMIT: Duration = Duration::from_secs(60);
/// Names the socket file (`.s.PGSQL.5432`); no TCP port is opened.
const PORT: u16 = 5432;
const USER: &str = "breakshot";

pub struct Cluster {
    /// Connects to the cluster's `postgres` database.
    pub url: String,
    bin: PathBuf,
    data: PathBuf,
    /// PostgreSQL refuses to run as root: then every command runs as the `postgres` user.
    run_as: Option<String>,
    _dir: TempDir,
}

/// The folder holding `initdb` and `pg_ctl`: on the `PATH`, or Debian's
/// `/usr/lib/postgresql/VERSION/bin` (newest first).
fn server_binaries() -> Option<PathBuf> {
    let on_path = std::env::var_os("PATH").and_then(|path| {
        std::env::split_paths(&path)
            .find(|d| d.join("initdb").is_file() && d.join("pg_ctl").is_file())
    });
    on_path.or_else(|| {
        let mut versions: Vec<PathBuf> = std::fs::read_dir("/usr/lib/postgresql")
            .ok()?
            .filter_map(|e| e.ok().map(|e| e.path().join("bin")))
            .filter(|d| d.join("initdb").is_file())
            .collect();
        versions.sort();
        versions.pop()
    })
}

fn is_root() -> bool {
    run(Command::new("id").arg("-u"), None, LIMIT)
        .stdout
        .starts_with(b"0\n")
}

impl Cluster {
    /// Starts a cluster, or says why not and returns `None`.
    pub fn start(test: &str) -> Option<Cluster> {
        let Some(bin) = server_binaries() else {
            let why = format!(
                "SKIPPED {test}: no PostgreSQL server binaries (initdb, pg_ctl) on the PATH or in /usr/lib/postgresql; install Debian's postgresql package to run it"
            );
            if std::env::var("BREAKSHOT_REQUIRE_POSTGRES").is_ok_and(|v| v == "1") {
                panic!("{why} (BREAKSHOT_REQUIRE_POSTGRES=1)");
            }
            eprintln!("{why}");
            return None;
        };
        let dir = breakshot_testkit::scratch("pg");
        let run_as = is_root().then(|| "postgres".to_string());
        let root = dir.path().join("pg");
        std::fs::create_dir(&root).expect("a folder for the cluster");
        if let Some(user) = &run_as {
            // The scratch folder is private to root: let the postgres user through to its
            // own folder inside.
            set_mode(dir.path(), 0o711);
            run_ok(
                Command::new("chown").arg(format!("{user}:")).arg(&root),
                None,
                LIMIT,
                "chown",
            );
        }
        let data = root.join("data");
        let socket = root.join("socket");
        let cluster = Cluster {
            url: format!(
                "postgresql://{USER}@/postgres?host={}&port={PORT}",
                socket.display()
            ),
            bin,
            data,
            run_as,
            _dir: dir,
        };
        cluster.pg(
            "initdb",
            &[
                "-D",
                &cluster.path(&cluster.data),
                "-U",
                USER,
                "-A",
                "trust",
                "--no-sync",
                "-E",
                "UTF8",
                "--locale=C",
            ],
        );
        std::fs::create_dir(&socket).ok();
        if let Some(user) = &cluster.run_as {
            run(
                Command::new("chown").arg(format!("{user}:")).arg(&socket),
                None,
                LIMIT,
            );
        }
        let options = format!(
            "-c listen_addresses='' -k {} -p {PORT} -c fsync=off",
            socket.display()
        );
        let log = root.join("server.log");
        cluster.pg(
            "pg_ctl",
            &[
                "-D",
                &cluster.path(&cluster.data),
                "-l",
                &cluster.path(&log),
                "-o",
                &options,
                "-w",
                "-t",
                "60",
                "start",
            ],
        );
        Some(cluster)
    }

    fn path(&self, p: &Path) -> String {
        p.display().to_string()
    }

    /// Runs one of the server's programs (as the postgres user under root), failing the
    /// test with its output if it fails.
    fn pg(&self, program: &str, args: &[&str]) {
        let exe = self.bin.join(program);
        let mut command = match &self.run_as {
            Some(user) => {
                let mut c = Command::new("runuser");
                c.arg("-u").arg(user).arg("--").arg(&exe);
                c
            }
            None => Command::new(&exe),
        };
        command.args(args);
        run_ok(&mut command, None, LIMIT, &format!("{program} failed"));
    }
}

fn set_mode(path: &Path, mode: u32) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode))
        .expect("permissions of the scratch folder");
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let data = self.path(&self.data);
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            self.pg(
                "pg_ctl",
                &["-D", &data, "-m", "immediate", "-w", "-t", "30", "stop"],
            );
        }));
    }
}

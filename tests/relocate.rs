//! The binary leaves its source tree: it holds no path of its build in what it loads (its embedded
//! scenes are data, not paths), and a copy run from an empty folder elsewhere counts every built-in
//! scene.

use std::path::Path;
use std::process::Command;

/// The bytes of an ELF file's sections that are loaded or read at run time: every section but the
/// debugging ones (which name the build's folders by design, and which a program never reads).
#[cfg(target_os = "linux")]
fn loaded_sections(elf: &[u8]) -> Vec<(String, &[u8])> {
    let u16_at = |o: usize| u16::from_le_bytes(elf[o..o + 2].try_into().unwrap()) as usize;
    let u32_at = |o: usize| u32::from_le_bytes(elf[o..o + 4].try_into().unwrap()) as usize;
    let u64_at = |o: usize| u64::from_le_bytes(elf[o..o + 8].try_into().unwrap()) as usize;
    assert_eq!(&elf[..4], b"\x7fELF", "an ELF file");
    assert_eq!(elf[4], 2, "64-bit ELF");
    assert_eq!(elf[5], 1, "little-endian ELF");
    let (shoff, shentsize, shnum, shstrndx) =
        (u64_at(0x28), u16_at(0x3a), u16_at(0x3c), u16_at(0x3e));
    let header = |i: usize| shoff + i * shentsize;
    let names = u64_at(header(shstrndx) + 0x18);
    (0..shnum)
        .filter_map(|i| {
            let h = header(i);
            let name_at = names + u32_at(h);
            let end = elf[name_at..].iter().position(|&b| b == 0).unwrap();
            let name = String::from_utf8_lossy(&elf[name_at..name_at + end]).into_owned();
            const NOBITS: usize = 8;
            if u32_at(h + 4) == NOBITS || name.starts_with(".debug") {
                return None;
            }
            let (off, size) = (u64_at(h + 0x18), u64_at(h + 0x20));
            Some((name, &elf[off..off + size]))
        })
        .collect()
}

#[cfg(target_os = "linux")]
#[test]
fn the_binary_holds_no_path_of_its_build() {
    let elf = std::fs::read(env!("CARGO_BIN_EXE_tetwalk")).unwrap();
    let sections = loaded_sections(&elf);
    assert!(sections.iter().any(|(n, _)| n == ".rodata"), "no .rodata");
    let root = env!("CARGO_MANIFEST_DIR").as_bytes();
    for (name, bytes) in &sections {
        assert!(
            !bytes.windows(root.len()).any(|w| w == root),
            "section {name} of the binary holds the source tree's path {}",
            env!("CARGO_MANIFEST_DIR")
        );
    }
}

/// `cmd`'s output, started again while the system says its program is busy: a file just copied can be
/// held open for writing a moment longer by another test's child between its fork and its exec
/// ("Text file busy"), which is not this test's failure.
fn output_once_free(cmd: &mut Command) -> std::process::Output {
    for _ in 0..200 {
        match cmd.output() {
            Err(e) if e.raw_os_error() == Some(libc::ETXTBSY) => {
                std::thread::sleep(std::time::Duration::from_millis(10));
            }
            other => return other.unwrap(),
        }
    }
    cmd.output().unwrap()
}

#[test]
fn a_copy_of_the_binary_counts_every_built_in_scene_from_an_empty_folder() {
    let away = tempfile::tempdir().unwrap();
    let bin = away.path().join("bin").join("tetwalk");
    std::fs::create_dir_all(bin.parent().unwrap()).unwrap();
    std::fs::copy(env!("CARGO_BIN_EXE_tetwalk"), &bin).unwrap();
    let work = away.path().join("work");
    std::fs::create_dir_all(&work).unwrap();
    for scene in tetwalk::scenes::BUILT_IN {
        let out = output_once_free(
            Command::new(&bin)
                .args(["count", "--scene", scene, "--views", "2", "--size", "12x12"])
                .args(["--methods", "maria17", "--json", "count.json"])
                .current_dir(&work)
                .env_remove("TETWALK_SCENES"),
        );
        assert!(
            out.status.success(),
            "{scene}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let report: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(work.join("count.json")).unwrap())
                .unwrap();
        assert_eq!(report["settings"]["scene"], *scene);
        assert_eq!(report["rays"], 2 * 12 * 12, "{scene}: every ray judged");
    }
    assert!(
        !Path::new(&work).join("corpora").exists(),
        "nothing of a source tree was made"
    );
}

/// The scene built on a machine is found where `TETWALK_SCENES` says, and its absence is explained.
#[test]
fn a_scene_built_here_is_found_by_tetwalk_scenes() {
    let dir = tempfile::tempdir().unwrap();
    let run = |scenes: &Path| {
        Command::new(env!("CARGO_BIN_EXE_tetwalk"))
            .args(["scene", "info", "bunny-paper", "--depth", "3"])
            .current_dir(dir.path())
            .env("TETWALK_SCENES", scenes)
            .output()
            .unwrap()
    };
    let out = run(dir.path());
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bunny-paper.sh") && err.contains("TETWALK_SCENES"),
        "{err}"
    );
    // Any TetGen mesh under that name will do: a built-in one's files, copied.
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("corpora/scenes");
    for ext in ["node", "ele", "neigh", "face"] {
        std::fs::copy(
            src.join(format!("bunny-cdt.{ext}")),
            dir.path().join(format!("bunny-paper.{ext}")),
        )
        .unwrap();
    }
    let out = run(dir.path());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("scene bunny-paper"));
}

; ringlab's Windows installer (NSIS 3, Modern UI 2). build-windows.sh runs
;   makensis -DVERSION=0.1.0 -DEXE=.../ringlab.exe -DOUTFILE=.../ringlab-setup.exe [-DICON=...ico] ringlab.nsi
; It installs ringlab.exe into Program Files\ringlab for all users, a Start-menu entry, a desktop
; shortcut if ticked, and an uninstaller listed in Settings > Apps (Add/Remove Programs).
; Silent: ringlab-setup.exe /S [/D=C:\other\folder]; uninstall.exe /S.

!ifndef VERSION
  !error "pass the version: makensis -DVERSION=x.y.z (build-windows.sh reads it from Cargo.toml)"
!endif
!ifndef EXE
  !error "pass the program: makensis -DEXE=path/to/ringlab.exe"
!endif
!ifndef OUTFILE
  !define OUTFILE "ringlab-setup.exe"
!endif

!define APP "ringlab"
!define UNINST_KEY "Software\Microsoft\Windows\CurrentVersion\Uninstall\${APP}"
!define APP_PATHS_KEY "Software\Microsoft\Windows\CurrentVersion\App Paths\ringlab.exe"

; A 64-bit installer (the program is 64-bit anyway): it also runs under a plain 64-bit Wine.
Target amd64-unicode
ManifestDPIAware true
SetCompressor /SOLID lzma
RequestExecutionLevel admin

Name "${APP} ${VERSION}"
OutFile "${OUTFILE}"
InstallDir "$PROGRAMFILES64\${APP}"
InstallDirRegKey HKLM "${UNINST_KEY}" "InstallLocation"
BrandingText "${APP} ${VERSION}"

VIProductVersion "${VERSION}.0"
VIAddVersionKey "ProductName" "${APP}"
VIAddVersionKey "ProductVersion" "${VERSION}"
VIAddVersionKey "FileVersion" "${VERSION}"
VIAddVersionKey "FileDescription" "${APP} installer: rolling rings, simulated, shown and fitted"
VIAddVersionKey "LegalCopyright" "MIT OR Apache-2.0"

!include "MUI2.nsh"
!include "x64.nsh"
!include "FileFunc.nsh"

!ifdef ICON
  !define MUI_ICON "${ICON}"
  !define MUI_UNICON "${ICON}"
  !define SHORTCUT_ICON "$INSTDIR\ringlab.ico"
!else
  !define SHORTCUT_ICON "$INSTDIR\ringlab.exe"
!endif
!define MUI_ABORTWARNING
!define MUI_FINISHPAGE_RUN "$INSTDIR\ringlab.exe"
!define MUI_FINISHPAGE_RUN_TEXT "Open ringlab now"

!insertmacro MUI_PAGE_WELCOME
!insertmacro MUI_PAGE_COMPONENTS
!insertmacro MUI_PAGE_DIRECTORY
!insertmacro MUI_PAGE_INSTFILES
!insertmacro MUI_PAGE_FINISH
!insertmacro MUI_UNPAGE_CONFIRM
!insertmacro MUI_UNPAGE_INSTFILES
!insertmacro MUI_LANGUAGE "English"

Function .onInit
  ${IfNot} ${RunningX64}
    MessageBox MB_ICONSTOP "ringlab needs 64-bit Windows." /SD IDOK
    Abort
  ${EndIf}
  SetRegView 64
  SetShellVarContext all
FunctionEnd

Function un.onInit
  SetRegView 64
  SetShellVarContext all
FunctionEnd

Section "ringlab (required)" SecMain
  SectionIn RO
  SetOutPath "$INSTDIR"
  File "/oname=ringlab.exe" "${EXE}"
  !ifdef ICON
    File "/oname=ringlab.ico" "${ICON}"
  !endif
  WriteUninstaller "$INSTDIR\uninstall.exe"

  CreateShortCut "$SMPROGRAMS\ringlab.lnk" "$INSTDIR\ringlab.exe" "" "${SHORTCUT_ICON}" 0 \
    SW_SHOWNORMAL "" "Rolling rings: the terminal retrograde turn, simulated and explained"

  ; Win+R "ringlab" finds it.
  WriteRegStr HKLM "${APP_PATHS_KEY}" "" "$INSTDIR\ringlab.exe"

  WriteRegStr HKLM "${UNINST_KEY}" "DisplayName" "${APP}"
  WriteRegStr HKLM "${UNINST_KEY}" "DisplayVersion" "${VERSION}"
  WriteRegStr HKLM "${UNINST_KEY}" "Publisher" "ringlab"
  WriteRegStr HKLM "${UNINST_KEY}" "DisplayIcon" "${SHORTCUT_ICON}"
  WriteRegStr HKLM "${UNINST_KEY}" "InstallLocation" "$INSTDIR"
  WriteRegStr HKLM "${UNINST_KEY}" "UninstallString" '"$INSTDIR\uninstall.exe"'
  WriteRegStr HKLM "${UNINST_KEY}" "QuietUninstallString" '"$INSTDIR\uninstall.exe" /S'
  WriteRegDWORD HKLM "${UNINST_KEY}" "NoModify" 1
  WriteRegDWORD HKLM "${UNINST_KEY}" "NoRepair" 1
  ${GetSize} "$INSTDIR" "/S=0K" $0 $1 $2
  IntFmt $0 "0x%08X" $0
  WriteRegDWORD HKLM "${UNINST_KEY}" "EstimatedSize" "$0"
SectionEnd

Section /o "Desktop shortcut" SecDesktop
  CreateShortCut "$DESKTOP\ringlab.lnk" "$INSTDIR\ringlab.exe" "" "${SHORTCUT_ICON}" 0
SectionEnd

!insertmacro MUI_FUNCTION_DESCRIPTION_BEGIN
  !insertmacro MUI_DESCRIPTION_TEXT ${SecMain} "ringlab.exe, its Start-menu entry and the uninstaller."
  !insertmacro MUI_DESCRIPTION_TEXT ${SecDesktop} "A ringlab icon on the desktop of every user."
!insertmacro MUI_FUNCTION_DESCRIPTION_END

Section "Uninstall"
  Delete "$SMPROGRAMS\ringlab.lnk"
  Delete "$DESKTOP\ringlab.lnk"
  Delete "$INSTDIR\ringlab.exe"
  Delete "$INSTDIR\ringlab.ico"
  Delete "$INSTDIR\uninstall.exe"
  ; Only if empty: files a user put there stay.
  RMDir "$INSTDIR"
  DeleteRegKey HKLM "${APP_PATHS_KEY}"
  DeleteRegKey HKLM "${UNINST_KEY}"
SectionEnd
